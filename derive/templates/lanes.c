/*
{{HEADER}}
*/
/* The model's right-hand side in the lanes of a GNU C vector: every double a bm_vec and the
 * functions applied lane by lane (bm_v_<function>), both defined by templates/batch_map.c,
 * after which this function is compiled (chaplygin.derive.emit.c_sources.batch_source). */
{{FUNCTION}}
