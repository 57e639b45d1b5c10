/*
{{HEADER}}
*/
/* C99 translation of one chaplygin model. Every routine has the signature
 *     void chaplygin_<routine>(double T, const double *restrict Y,
 *                              const double *restrict P, double *restrict OUT);
 * Y holds the state (CHAPLYGIN_N_STATE doubles, order in the header), P the parameters,
 * OUT the result (the Jacobian is row-major, CHAPLYGIN_N_STATE^2 doubles).
 * State and parameter values are unpacked into local constants named s_<name> and
 * p_<name>, so the printed expressions need no string surgery.
 */
#include <math.h>
#include <stddef.h>

#include "detmath.h" /* chaplygin/arith/templates/detmath.h, inlined when compiled */

#define CHAPLYGIN_N_STATE {{N_STATE}}
#define CHAPLYGIN_N_PARAM {{N_PARAM}}
#define CHAPLYGIN_N_AUX {{N_AUX}}
#define CHAPLYGIN_N_INTEGRALS {{N_INTEGRALS}}

const char *chaplygin_model_hash(void) { return "{{MODEL_HASH}}"; }

void chaplygin_sizes(int *OUT)
{
    OUT[0] = CHAPLYGIN_N_STATE;
    OUT[1] = CHAPLYGIN_N_PARAM;
    OUT[2] = CHAPLYGIN_N_AUX;
    OUT[3] = CHAPLYGIN_N_INTEGRALS;
}

{{ROUTINES}}
