/*
{{HEADER}}
*/
/* Taylor coefficients of one chaplygin model on Arb balls and first-order jets (emitted by
 * chaplygin.derive.emit.taylor_arb from the model's Taylor program), for the validated
 * integrator (chaplygin.numerics.validated): the recurrences of the Python module
 * (*_taylor.py) run on ArbJet numbers, as in-place Arb calls of FLINT 3 at the run's
 * precision. Every node keeps its value series and, when it depends on the state, one series
 * per seed of its gradient; a convolution is one arb_dot per series (value, then each
 * gradient component as two dots), a quotient's jet is (u' - q w') / w as in ArbJet.
 *
 * No FLINT header is needed: the few types and functions used are declared below, for the
 * FLINT 3 library python-flint loads (its wheel's libflint). The loader
 * (chaplygin.numerics.validated.arb_kernel) checks the FLINT version and the size of a ball
 * against python-flint before it calls anything here.
 *
 * Numbers cross the interface as pointers to Arb balls (the balls of python-flint's objects):
 *
 *   chaplygin_taylor_arb(prec, order, m, T0, Y, YG, P, OUT, OUTG)
 *
 * T0 the expansion time, Y the n state balls, YG their n x m gradients (m = 0: plain balls,
 * YG and OUTG unused), P the parameters; OUT receives the coefficients 0..order of each state
 * component (row-major, n x (order + 1)) and OUTG their gradients ((n x (order + 1)) x m).
 */
#include <stddef.h>
#include <stdlib.h>

typedef long slong;
typedef unsigned long ulong;
/* arb_struct of FLINT 3: arf_struct (fmpz exp, slong size, two limbs or a pointer: 32 bytes)
   and mag_struct (fmpz exp, ulong man: 16 bytes). Only its size is used here. */
typedef struct { slong words[6]; } arb_struct;
typedef arb_struct *arb_ptr;
typedef const arb_struct *arb_srcptr;

extern const char flint_version[];
arb_ptr _arb_vec_init(slong n);
void _arb_vec_clear(arb_ptr v, slong n);
void arb_set(arb_ptr y, arb_srcptr x);
void arb_zero(arb_ptr x);
void arb_one(arb_ptr x);
void arb_set_si(arb_ptr x, slong y);
void arb_neg(arb_ptr y, arb_srcptr x);
void arb_add(arb_ptr z, arb_srcptr x, arb_srcptr y, slong prec);
void arb_sub(arb_ptr z, arb_srcptr x, arb_srcptr y, slong prec);
void arb_mul(arb_ptr z, arb_srcptr x, arb_srcptr y, slong prec);
void arb_div(arb_ptr z, arb_srcptr x, arb_srcptr y, slong prec);
void arb_addmul(arb_ptr z, arb_srcptr x, arb_srcptr y, slong prec);
void arb_submul(arb_ptr z, arb_srcptr x, arb_srcptr y, slong prec);
void arb_mul_si(arb_ptr z, arb_srcptr x, slong y, slong prec);
void arb_div_si(arb_ptr z, arb_srcptr x, slong y, slong prec);
void arb_mul_2exp_si(arb_ptr y, arb_srcptr x, slong e);
void arb_sqrt(arb_ptr z, arb_srcptr x, slong prec);
void arb_exp(arb_ptr z, arb_srcptr x, slong prec);
void arb_sin_cos(arb_ptr s, arb_ptr c, arb_srcptr x, slong prec);
void arb_pow(arb_ptr z, arb_srcptr x, arb_srcptr y, slong prec);
void arb_const_pi(arb_ptr x, slong prec);
void arb_dot(arb_ptr res, arb_srcptr initial, int subtract, arb_srcptr x, slong xstep,
             arb_srcptr y, slong ystep, slong len, slong prec);
int arb_equal(arb_srcptr x, arb_srcptr y);

#define N_STATE {{N_STATE}}
#define N_PARAM {{N_PARAM}}
#define N_NODES {{N_NODES}}
#define N_CONST_TMP {{N_CONST_TMP}}
#define MAX_SEEDS 64

const char *chaplygin_taylor_model_hash(void) { return "{{MODEL_HASH}}"; }
const char *chaplygin_arb_flint_version(void) { return flint_version; }
int chaplygin_arb_ball_size(void) { return (int)sizeof(arb_struct); }

void chaplygin_taylor_sizes(int *OUT)
{
    OUT[0] = N_STATE;
    OUT[1] = N_PARAM;
    OUT[2] = N_NODES;
    OUT[3] = MAX_SEEDS;
}

/* The loader's check that balls are where python-flint keeps them: X must hold 1/3 at
   prec bits as python-flint computes it; Y (a fresh ball) receives 2/3 computed here. */
int chaplygin_arb_probe(arb_srcptr X, arb_ptr Y, slong prec)
{
    arb_ptr t = _arb_vec_init(2);
    int same;
    arb_set_si(t, 1);
    arb_div_si(t, t, 3, prec);
    same = arb_equal(t, X);
    arb_set_si(t + 1, 2);
    arb_div_si(Y, t + 1, 3, prec);
    _arb_vec_clear(t, 2);
    return same;
}

/* ------------------------------------------------------------------ workspace */
typedef struct {
    slong prec;
    int S, m;             /* coefficients per series (order + 1), seeds */
    arb_ptr V;            /* N_NODES x S values */
    arb_ptr G;            /* N_NODES x m x S gradients */
    arb_ptr T1, T2;       /* weighted series, S each */
    arb_ptr nv, ng;       /* a jet temporary: value, m gradient components */
    arb_ptr dv, dg;       /* a divisor jet */
    arb_ptr t;            /* scalar temporaries (4) */
    arb_ptr c;            /* temporaries of the constants */
    arb_srcptr *P;
} ws_t;

#define V(i, k) (w->V + (size_t)(i) * w->S + (k))
#define G(i, c, k) (w->G + ((size_t)(i) * w->m + (c)) * w->S + (k))
#define PREC (w->prec)

/* x_k = a_k + s b_k (s = 1 add, -1 sub; b < 0: x_k = s a_k, a copy or a negation) */
static void j_lin(ws_t *w, int x, int a, int b, int s, int k, int ga, int gb)
{
    int c;
    if (b < 0) {
        if (s > 0) arb_set(V(x, k), V(a, k)); else arb_neg(V(x, k), V(a, k));
        if (ga)
            for (c = 0; c < w->m; ++c)
                if (s > 0) arb_set(G(x, c, k), G(a, c, k)); else arb_neg(G(x, c, k), G(a, c, k));
        return;
    }
    if (s > 0) arb_add(V(x, k), V(a, k), V(b, k), PREC); else arb_sub(V(x, k), V(a, k), V(b, k), PREC);
    for (c = 0; c < w->m && (ga || gb); ++c) {
        if (ga && gb) {
            if (s > 0) arb_add(G(x, c, k), G(a, c, k), G(b, c, k), PREC);
            else arb_sub(G(x, c, k), G(a, c, k), G(b, c, k), PREC);
        } else if (ga) {
            arb_set(G(x, c, k), G(a, c, k));
        } else if (s > 0) {
            arb_set(G(x, c, k), G(b, c, k));
        } else {
            arb_neg(G(x, c, k), G(b, c, k));
        }
    }
}

/* x_k = a_k * q_0 (q a constant node) */
static void j_scale(ws_t *w, int x, int a, int q, int k, int ga)
{
    arb_mul(V(x, k), V(a, k), V(q, 0), PREC);
    if (ga)
        for (int c = 0; c < w->m; ++c) arb_mul(G(x, c, k), G(a, c, k), V(q, 0), PREC);
}

/* the jet (w->nv, w->ng) = sum_(j = lo..hi) wt_j a_j b_(k - j), wt_j = j when weighted, else 1 */
static void j_conv(ws_t *w, int a, int b, int lo, int hi, int k, int weighted, int ga, int gb)
{
    slong len = hi - lo + 1;
    int c, j;
    arb_srcptr aw;
    if (len <= 0) {
        arb_zero(w->nv);
        for (c = 0; c < w->m; ++c) arb_zero(w->ng + c);
        return;
    }
    if (weighted) {
        for (j = lo; j <= hi; ++j) arb_mul_si(w->T1 + j, V(a, j), j, PREC);
        aw = w->T1 + lo;
    } else {
        aw = V(a, lo);
    }
    arb_dot(w->nv, NULL, 0, aw, 1, V(b, k - lo), -1, len, PREC);
    for (c = 0; c < w->m && (ga || gb); ++c) {
        arb_ptr g = w->ng + c;
        arb_srcptr first = NULL;
        if (ga) {
            arb_srcptr gaw = G(a, c, lo);
            if (weighted) {
                for (j = lo; j <= hi; ++j) arb_mul_si(w->T2 + j, G(a, c, j), j, PREC);
                gaw = w->T2 + lo;
            }
            arb_dot(g, NULL, 0, gaw, 1, V(b, k - lo), -1, len, PREC);
            first = g;
        }
        if (gb) {
            arb_dot(g, first, 0, aw, 1, G(b, c, k - lo), -1, len, PREC);
        }
        if (!ga && !gb) arb_zero(g);
    }
}

/* x_k = the jet temporary */
static void j_store(ws_t *w, int x, int k, int gn)
{
    arb_set(V(x, k), w->nv);
    for (int c = 0; c < w->m && gn; ++c) arb_set(G(x, c, k), w->ng + c);
}

/* the jet temporary negated (s < 0) and/or subtracted from a_k (a >= 0): n = a_k - n, or -n */
static void j_from(ws_t *w, int a, int k, int ga, int gn)
{
    int c;
    if (a >= 0) {
        arb_sub(w->nv, V(a, k), w->nv, PREC);
        for (c = 0; c < w->m; ++c) {
            if (ga && gn) arb_sub(w->ng + c, G(a, c, k), w->ng + c, PREC);
            else if (ga) arb_set(w->ng + c, G(a, c, k));
            else if (gn) arb_neg(w->ng + c, w->ng + c);
        }
    } else {
        arb_neg(w->nv, w->nv);
        for (c = 0; c < w->m && gn; ++c) arb_neg(w->ng + c, w->ng + c);
    }
}

/* x_k = n / d, jets: q = n/d, (n' - q d') / d (as ArbJet.__truediv__); gn, gd: have gradients */
static void j_div_store(ws_t *w, int x, int k, int gn, int gd)
{
    arb_div(V(x, k), w->nv, w->dv, PREC);
    if (!gn && !gd) return;
    for (int c = 0; c < w->m; ++c) {
        arb_ptr g = G(x, c, k);
        if (gn) arb_set(w->t, w->ng + c); else arb_zero(w->t);
        if (gd) arb_submul(w->t, V(x, k), w->dg + c, PREC);
        arb_div(g, w->t, w->dv, PREC);
    }
}

/* the divisor jet d = s * b_0 (s an integer factor) */
static void j_divisor(ws_t *w, int b, slong s, int gb)
{
    arb_mul_si(w->dv, V(b, 0), s, PREC);
    for (int c = 0; c < w->m && gb; ++c) arb_mul_si(w->dg + c, G(b, c, 0), s, PREC);
}

/* x_k = n / k (the jet temporary divided by the order) */
static void j_div_k(ws_t *w, int x, int k, int gn)
{
    arb_div_si(V(x, k), w->nv, k, PREC);
    for (int c = 0; c < w->m && gn; ++c) arb_div_si(G(x, c, k), w->ng + c, k, PREC);
}

/* ------------------------------------------------------------------ order 0 */
/* x_0 = a_0 b_0 (jets) */
static void j_mul0(ws_t *w, int x, int a, int b, int ga, int gb)
{
    arb_mul(V(x, 0), V(a, 0), V(b, 0), PREC);
    for (int c = 0; c < w->m && (ga || gb); ++c) {
        arb_ptr g = G(x, c, 0);
        if (ga) arb_mul(g, G(a, c, 0), V(b, 0), PREC); else arb_zero(g);
        if (gb) arb_addmul(g, V(a, 0), G(b, c, 0), PREC);
    }
}

/* x_0 = a_0 / b_0 (jets) */
static void j_div0(ws_t *w, int x, int a, int b, int ga, int gb)
{
    int c;
    arb_set(w->nv, V(a, 0));
    for (c = 0; c < w->m && ga; ++c) arb_set(w->ng + c, G(a, c, 0));
    j_divisor(w, b, 1, gb);
    j_div_store(w, x, 0, ga, gb);
}

/* x_0 = f(a_0), f = sqrt, exp, sin, cos, pow (exponent p/q): the value, and the gradient as
   a_0' f'(a_0) */
enum { F_SQRT, F_EXP, F_SIN, F_COS, F_POW };
static void j_fn0(ws_t *w, int x, int a, int f, slong p, slong q, int ga)
{
    arb_ptr d = w->t + 1; /* f'(a_0) */
    switch (f) {
    case F_SQRT:
        arb_sqrt(V(x, 0), V(a, 0), PREC);
        arb_mul_2exp_si(d, V(x, 0), 1);
        arb_set_si(w->t + 2, 1);
        arb_div(d, w->t + 2, d, PREC);
        break;
    case F_EXP:
        arb_exp(V(x, 0), V(a, 0), PREC);
        arb_set(d, V(x, 0));
        break;
    case F_SIN:
        arb_sin_cos(V(x, 0), d, V(a, 0), PREC);
        break;
    case F_COS:
        arb_sin_cos(d, V(x, 0), V(a, 0), PREC);
        arb_neg(d, d);
        break;
    default: /* F_POW: a^r and r a^(r - 1) */
        arb_set_si(w->t + 2, p);
        arb_div_si(w->t + 2, w->t + 2, q, PREC);
        arb_pow(V(x, 0), V(a, 0), w->t + 2, PREC);
        arb_set_si(w->t + 3, p - q);
        arb_div_si(w->t + 3, w->t + 3, q, PREC);
        arb_pow(d, V(a, 0), w->t + 3, PREC);
        arb_mul(d, d, w->t + 2, PREC);
        break;
    }
    for (int c = 0; c < w->m && ga; ++c) arb_mul(G(x, c, 0), G(a, c, 0), d, PREC);
}

/* ------------------------------------------------------------------ higher orders */
/* pow: x_k = sum_(j<k) (p (k - j) - q j) a_(k-j) x_j / (q k a_0) */
static void j_pow(ws_t *w, int x, int a, slong p, slong q, int k, int ga)
{
    int j;
    for (j = 0; j < k; ++j) arb_mul_si(w->T1 + j, V(x, j), p * (k - j) - q * j, PREC);
    arb_dot(w->nv, NULL, 0, w->T1, 1, V(a, k), -1, k, PREC);
    for (int c = 0; c < w->m && ga; ++c) {
        arb_dot(w->ng + c, NULL, 0, w->T1, 1, G(a, c, k), -1, k, PREC);
        for (j = 0; j < k; ++j) arb_mul_si(w->T2 + j, G(x, c, j), p * (k - j) - q * j, PREC);
        arb_dot(w->ng + c, w->ng + c, 0, w->T2, 1, V(a, k), -1, k, PREC);
    }
    j_divisor(w, a, q * k, ga);
    j_div_store(w, x, k, ga, ga);
}

/* ------------------------------------------------------------------ the recurrences */
static void taylor_coefficients(ws_t *w, arb_srcptr T0, arb_srcptr *Y, arb_srcptr *YG, int order)
{
    int c;
    (void)c;
{{COEFFICIENTS}}
}

int chaplygin_taylor_arb(slong prec, int order, int m, arb_srcptr *T0, arb_srcptr *Y,
                         arb_srcptr *YG, arb_srcptr *P, arb_ptr *OUT, arb_ptr *OUTG)
{
    ws_t ws, *w = &ws;
    slong nV, nG;
    if (order < 1 || m < 0 || m > MAX_SEEDS) return 1;
    w->prec = prec;
    w->S = order + 1;
    w->m = m;
    nV = (slong)N_NODES * w->S;
    nG = nV * m;
    w->V = _arb_vec_init(nV + nG + 2 * w->S + 2 * (m + 1) + 4 + N_CONST_TMP + 1);
    w->G = w->V + nV;
    w->T1 = w->G + nG;
    w->T2 = w->T1 + w->S;
    w->nv = w->T2 + w->S;
    w->ng = w->nv + 1;
    w->dv = w->ng + m;
    w->dg = w->dv + 1;
    w->t = w->dg + m;
    w->c = w->t + 4;
    w->P = P;
    taylor_coefficients(w, T0[0], Y, YG, order);
    for (int i = 0; i < N_STATE; ++i)
        for (int k = 0; k <= order; ++k) {
            size_t at = (size_t)i * w->S + k;
            arb_set(OUT[at], V(i, k));
            for (int c = 0; c < m; ++c) arb_set(OUTG[at * m + c], G(i, c, k));
        }
    _arb_vec_clear(w->V, nV + nG + 2 * w->S + 2 * (m + 1) + 4 + N_CONST_TMP + 1);
    return 0;
}
