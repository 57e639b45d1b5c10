/*
{{HEADER}}
*/
/* Taylor integrator of one chaplygin model in MPFR (emitted by chaplygin.derive.emit.taylor,
 * language taylor_mpfr), for working precisions past quad-double. The recurrences are those
 * of the Taylor program of taylor.c and of the Python module (*_taylor.py), written as
 * in-place MPFR calls at the run's precision (round to nearest):
 *
 *   convolutions      tc_dot: exact products of the significands (mpn_mul) summed in fixed
 *                     point, rounded once, on arrays of pointers to the coefficients, one
 *                     forward and one reversed per node, so sum_j a_j b_(k-j) is one call;
 *   divisions by k    mpfr_div_ui.
 *
 * Numbers cross the interface exactly, as text: inputs are tokens separated by blanks in any
 * form mpfr_strtofr reads in base 16 ("-1a3fp-40", hexadecimal significand and binary
 * exponent: every binary number is exact), outputs are written by mpfr_snprintf "%Ra" (exact
 * hexadecimal) into fixed-width slots. The working storage (every node series, the pointer
 * arrays, the temporaries) is allocated once per call at the run's precision and order.
 *
 * Order and step follow numerics/taylor.py's Python stepper to the bit (Jorba & Zou 2005):
 * eps = atol if rtol |y|_inf <= atol (absolute control, scale 1) else eps = rtol, order
 * p = ceil(-ln(eps)/2 + 1) (at most MAX_ORDER), step h = rho e^f with
 * rho = min_k (scale/|y_[k]|_inf)^(1/k) over k = p-1, p (the logarithms in MPFR, their
 * difference rounded to double) and f = min(-2, ln(eps)/(p-1)) - 0.7/(p-1).
 *
 *   chaplygin_taylor_mpfr_coefficients(prec, order, T0, Y, P, OUT, width)
 *   chaplygin_taylor_mpfr_run(prec, T01, Y0, P, CTRL, FIXED_H, fixed_order, n_eval, T_EVAL,
 *                             Y_EVAL, width, Y_END, T_REACHED, max_steps, STATS)
 */
#include <math.h>
#include "detmath.h" /* chaplygin/arith/templates/detmath.h, inlined when compiled */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gmp.h>
#include <mpfr.h>

#if MPFR_VERSION < MPFR_VERSION_NUM(4, 1, 0)
#error "the MPFR Taylor integrator needs mpfr_dot (MPFR >= 4.1)"
#endif

#define CHAPLYGIN_TAYLOR_N_STATE {{N_STATE}}
#define CHAPLYGIN_TAYLOR_N_PARAM {{N_PARAM}}
#define CHAPLYGIN_TAYLOR_N_NODES {{N_NODES}}
/* rows of the workspace: the nodes, then the series j a_j of the exp/sin/cos arguments */
#define CHAPLYGIN_TAYLOR_N_ROWS {{N_ROWS}}
#define CHAPLYGIN_TAYLOR_N_CONST_TMP {{N_CONST_TMP}}
#define CHAPLYGIN_TAYLOR_MAX_ORDER {{MAX_ORDER}}

const char *chaplygin_taylor_model_hash(void) { return "{{MODEL_HASH}}"; }

/* the version of the MPFR library this code runs with (not of the header it was built with) */
const char *chaplygin_taylor_mpfr_version(void) { return mpfr_get_version(); }

void chaplygin_taylor_sizes(int *OUT)
{
    OUT[0] = CHAPLYGIN_TAYLOR_N_STATE;
    OUT[1] = CHAPLYGIN_TAYLOR_N_PARAM;
    OUT[2] = CHAPLYGIN_TAYLOR_N_NODES;
    OUT[3] = CHAPLYGIN_TAYLOR_MAX_ORDER;
    OUT[4] = 0; /* no fixed-size REAL */
}

/* ------------------------------------------------------------------ workspace */
typedef struct {
    int S;                 /* coefficients per row: largest order of the run + 1 */
    mpfr_t *X;             /* N_ROWS x S series */
    mpfr_ptr *fwd, *rev;   /* fwd[i S + j] = X[i S + j], rev[i S + m] = X[i S + S - 1 - m] */
    mpfr_t T0, s, t, e;    /* expansion time, sum and product temporaries, exponent */
    mpfr_t Y[CHAPLYGIN_TAYLOR_N_STATE];
    mpfr_t P[CHAPLYGIN_TAYLOR_N_PARAM + 1];
    mpfr_t c[CHAPLYGIN_TAYLOR_N_CONST_TMP + 1];  /* temporaries of the constants */
    mp_size_t window;                            /* limbs of the dot accumulators, + 1 */
    mp_limb_t *acc, *prod, *shifted;             /* 2 window, 2 limbs(prec), + 1 */
} ws_t;

#define A(i, k) (w->X[(size_t)(i) * w->S + (k)])
#define FWD(i, j) (w->fwd + (size_t)(i) * w->S + (j))
/* {x_k, x_(k-1), ..., x_0}: the reversed series ending at coefficient k */
#define REV(i, k) (w->rev + (size_t)(i) * w->S + (w->S - 1 - (k)))

static void ws_clear(ws_t *w)
{
    if (w->X != NULL) {
        for (size_t i = 0; i < (size_t)CHAPLYGIN_TAYLOR_N_ROWS * w->S; ++i) mpfr_clear(w->X[i]);
    }
    free(w->X);
    free(w->fwd);
    free(w->rev);
    free(w->acc);
    mpfr_clears(w->T0, w->s, w->t, w->e, (mpfr_ptr)0);
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i) mpfr_clear(w->Y[i]);
    for (int i = 0; i <= CHAPLYGIN_TAYLOR_N_PARAM; ++i) mpfr_clear(w->P[i]);
    for (int i = 0; i <= CHAPLYGIN_TAYLOR_N_CONST_TMP; ++i) mpfr_clear(w->c[i]);
}

/* Bits of coefficient k: prec, or with taper (the adaptive loop) prec less 2k/ln 2 plus
 * TAPER_GUARD bits, at least TAPER_FLOOR. The step makes |y_[k]| h^k about scale e^(-2k)
 * (Jorba & Zou: h = rho e^-2 .., rho^-k the coefficients' decay), so a relative error
 * 2^-(prec - 2k/ln 2) of y_[k] adds about scale 2^-prec e^(-2k) e^(2k) = scale 2^-prec to the
 * new state: the rounding of the high orders stays 2^-TAPER_GUARD below the working
 * precision. (When the decay is slower than the estimate the truncation error grows by the
 * same factor, and stays TAPER_GUARD bits above this one.) */
#define TAPER_GUARD 32
#define TAPER_FLOOR 64
static mpfr_prec_t coefficient_prec(mpfr_prec_t prec, int k, int taper)
{
    if (!taper) return prec;
    long bits = (long)prec - (long)(2.8853900817779268 * k) + TAPER_GUARD;
    if (bits > (long)prec) bits = (long)prec;
    if (bits < TAPER_FLOOR) bits = prec < TAPER_FLOOR ? (long)prec : TAPER_FLOOR;
    return (mpfr_prec_t)bits;
}

/* All series, zero (the time's and constants' rows stay zero past the coefficients the
 * recurrences write); coefficient k at coefficient_prec(prec, k, taper). Returns 0, or -4
 * without memory. */
static int ws_init(ws_t *w, mpfr_prec_t prec, int max_order, int taper)
{
    const size_t S = (size_t)max_order + 1, n = (size_t)CHAPLYGIN_TAYLOR_N_ROWS * S;
    w->S = (int)S;
    mpfr_inits2(prec, w->T0, w->s, w->t, w->e, (mpfr_ptr)0);
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i) mpfr_init2(w->Y[i], prec);
    for (int i = 0; i <= CHAPLYGIN_TAYLOR_N_PARAM; ++i) mpfr_init2(w->P[i], prec);
    for (int i = 0; i <= CHAPLYGIN_TAYLOR_N_CONST_TMP; ++i) mpfr_init2(w->c[i], prec);
    /* the dot accumulators: limbs(prec) + 1 fraction limbs below the largest product's
     * exponent (64 bits past the working precision) and one limb for the carries */
    const mp_size_t nl = (mp_size_t)((prec + GMP_NUMB_BITS - 1) / GMP_NUMB_BITS);
    w->window = nl + 2;
    w->acc = malloc(sizeof(mp_limb_t) * (size_t)(2 * w->window + 2 * nl + 2 * nl + 1));
    w->prod = w->acc == NULL ? NULL : w->acc + 2 * w->window;
    w->shifted = w->prod == NULL ? NULL : w->prod + 2 * nl;
    w->X = malloc(sizeof(mpfr_t) * n);
    w->fwd = malloc(sizeof(mpfr_ptr) * n);
    w->rev = malloc(sizeof(mpfr_ptr) * n);
    if (w->X == NULL || w->fwd == NULL || w->rev == NULL || w->acc == NULL) {
        free(w->X);
        w->X = NULL;
        ws_clear(w);
        return -4;
    }
    for (size_t i = 0; i < n; ++i) {
        mpfr_init2(w->X[i], coefficient_prec(prec, (int)(i % S), taper));
        mpfr_set_zero(w->X[i], 1);
    }
    for (size_t r = 0; r < (size_t)CHAPLYGIN_TAYLOR_N_ROWS; ++r)
        for (size_t j = 0; j < S; ++j) {
            w->fwd[r * S + j] = w->X[r * S + j];
            w->rev[r * S + j] = w->X[r * S + (S - 1 - j)];
        }
    return 0;
}

/* ------------------------------------------------------------------ recurrences */
/* acc (window limbs) += p (np limbs) 2^pos, the bits below 2^0 dropped (pos < 0) */
static void acc_add(ws_t *w, mp_limb_t *acc, const mp_limb_t *p, mp_size_t np, long pos)
{
    const mp_size_t W = w->window;
    mp_limb_t *tmp = w->shifted;
    if (pos >= 0) {
        const mp_size_t off = pos / GMP_NUMB_BITS;
        const unsigned sh = (unsigned)(pos % GMP_NUMB_BITS);
        if (off >= W) return; /* cannot happen: products are below the largest */
        if (sh) tmp[np] = mpn_lshift(tmp, p, np, sh);
        else {
            memcpy(tmp, p, sizeof(mp_limb_t) * (size_t)np);
            tmp[np] = 0;
        }
        mp_size_t len = np + 1;
        if (off + len > W) len = W - off; /* the limbs past the window are zero */
        mp_limb_t cy = mpn_add_n(acc + off, acc + off, tmp, len);
        if (cy && off + len < W) mpn_add_1(acc + off + len, acc + off + len, W - off - len, cy);
    } else {
        const long r = -pos;
        const mp_size_t drop = r / GMP_NUMB_BITS;
        const unsigned sh = (unsigned)(r % GMP_NUMB_BITS);
        if (drop >= np) return;
        mp_size_t m = np - drop;
        if (sh) mpn_rshift(tmp, p + drop, m, sh);
        else memcpy(tmp, p + drop, sizeof(mp_limb_t) * (size_t)m);
        if (m > W) m = W; /* the limbs past the window are zero */
        mp_limb_t cy = mpn_add_n(acc, acc, tmp, m);
        if (cy && m < W) mpn_add_1(acc + m, acc + m, W - m, cy);
    }
}

/* rop = sum_{j<n} a[j] b[j] (0 for n = 0). The products are formed exactly on the limbs
 * (mpn_mul) and added in fixed point, positive and negative apart, on a window of
 * limbs(prec) + 1 limbs below the largest product's exponent 2^E; bits below the window are
 * dropped, so the sum is exact to n 2^(E - 64 (limbs(prec) + 1)) -- at least 64 bits below
 * the working precision relative to the largest term -- and then rounded once to rop.
 * (mpfr_dot is correctly rounded but costs about twice as much: it is the fallback for NaN
 * and infinite terms.) */
static void tc_dot(ws_t *w, mpfr_ptr rop, mpfr_ptr *a, mpfr_ptr *b, unsigned long n)
{
    mpfr_exp_t emax = 0;
    int any = 0;
    for (unsigned long j = 0; j < n; ++j) {
        if (mpfr_zero_p(a[j]) || mpfr_zero_p(b[j])) continue;
        if (!mpfr_regular_p(a[j]) || !mpfr_regular_p(b[j])) {
            mpfr_dot(rop, a, b, n, MPFR_RNDN);
            return;
        }
        mpfr_exp_t e = mpfr_get_exp(a[j]) + mpfr_get_exp(b[j]);
        if (!any || e > emax) emax = e;
        any = 1;
    }
    if (!any) {
        mpfr_set_zero(rop, 1);
        return;
    }
    const mp_size_t W = w->window;
    mp_limb_t *pos = w->acc, *neg = w->acc + W;
    memset(w->acc, 0, sizeof(mp_limb_t) * (size_t)(2 * W));
    /* accumulator unit: 2^(emax - 64 (W - 1)); a product of na + nb limbs is
     * P 2^(ea + eb - 64 (na + nb)) */
    for (unsigned long j = 0; j < n; ++j) {
        if (mpfr_zero_p(a[j]) || mpfr_zero_p(b[j])) continue;
        mpfr_srcptr x = a[j], y = b[j];
        mp_size_t nx = (mp_size_t)((mpfr_get_prec(x) + GMP_NUMB_BITS - 1) / GMP_NUMB_BITS);
        mp_size_t ny = (mp_size_t)((mpfr_get_prec(y) + GMP_NUMB_BITS - 1) / GMP_NUMB_BITS);
        if (nx < ny) {
            mpfr_srcptr tz = x;
            x = y;
            y = tz;
            mp_size_t tn = nx;
            nx = ny;
            ny = tn;
        }
        mpn_mul(w->prod, (const mp_limb_t *)mpfr_custom_get_significand(x), nx,
                (const mp_limb_t *)mpfr_custom_get_significand(y), ny);
        const long e = (long)(mpfr_get_exp(x) + mpfr_get_exp(y));
        const long shift = e - (long)GMP_NUMB_BITS * (long)(nx + ny) - (long)emax
                           + (long)GMP_NUMB_BITS * (long)(W - 1);
        const int negative = (mpfr_signbit(x) != 0) != (mpfr_signbit(y) != 0);
        acc_add(w, negative ? neg : pos, w->prod, nx + ny, shift);
    }
    int sign = 1;
    if (mpn_cmp(pos, neg, W) >= 0) mpn_sub_n(pos, pos, neg, W);
    else {
        mpn_sub_n(pos, neg, pos, W);
        sign = -1;
    }
    mpz_t z;
    mpz_roinit_n(z, pos, sign * W);
    mpfr_set_z_2exp(rop, z, emax - (mpfr_exp_t)GMP_NUMB_BITS * (W - 1), MPFR_RNDN);
}

/* c = a^(p/q): c_k = sum_{j<k} (p (k-j) - q j) a_{k-j} c_j / (q k a_0) */
static inline void tc_pow(ws_t *w, int a, int c, long p, long q, int k)
{
    mpfr_set_zero(w->s, 1);
    for (int j = 0; j < k; ++j) {
        mpfr_mul(w->t, A(a, k - j), A(c, j), MPFR_RNDN);
        mpfr_mul_si(w->t, w->t, p * (k - j) - q * j, MPFR_RNDN);
        mpfr_add(w->s, w->s, w->t, MPFR_RNDN);
    }
    mpfr_mul_si(w->t, A(a, 0), q * k, MPFR_RNDN);
    mpfr_div(A(c, k), w->s, w->t, MPFR_RNDN);
}

{{COEFFICIENTS}}

/* ------------------------------------------------------------------ text interface */
/* Read n numbers (base 16 tokens separated by blanks) from *text into x; advances *text.
 * Returns 0, or -5 for a malformed token. */
static int read_numbers(const char **text, mpfr_t *x, int n)
{
    const char *s = *text;
    for (int i = 0; i < n; ++i) {
        char *end;
        while (*s == ' ') ++s;
        mpfr_strtofr(x[i], s, &end, 16, MPFR_RNDN);
        if (end == s) return -5;
        s = end;
    }
    *text = s;
    return 0;
}

static int read_number(const char **text, mpfr_ptr x)
{
    mpfr_t *slot = (mpfr_t *)x; /* an mpfr_t is an array of one struct */
    return read_numbers(text, slot, 1);
}

static void write_number(char *out, int width, mpfr_srcptr x)
{
    mpfr_snprintf(out, (size_t)width, "%Ra", x);
}

static int taylor_order(double eps)
{
    int p = (int)ceil(-0.5 * chaplygin_log(eps) + 1.0);
    if (p < 2) p = 2;
    if (p > CHAPLYGIN_TAYLOR_MAX_ORDER) p = CHAPLYGIN_TAYLOR_MAX_ORDER;
    return p;
}

/* Normalised Taylor coefficients y_i^(k)(t0)/k!, k = 0..order, at precision prec, written
 * row by row (n_state x (order+1) slots of width chars). Returns 0, -4 (no memory), -5 (a
 * malformed number), -7 (order out of range). */
int chaplygin_taylor_mpfr_coefficients(long prec, int order, const char *T0, const char *Y,
                                       const char *P, char *OUT, int width)
{
    if (order < 1 || order > CHAPLYGIN_TAYLOR_MAX_ORDER) return -7;
    ws_t w;
    if (ws_init(&w, (mpfr_prec_t)prec, order, 0)) return -4;
    int status = read_number(&T0, w.T0);
    if (!status) status = read_numbers(&Y, w.Y, CHAPLYGIN_TAYLOR_N_STATE);
    if (!status) status = read_numbers(&P, w.P, CHAPLYGIN_TAYLOR_N_PARAM);
    if (!status) {
        taylor_coefficients(order, &w);
        for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i)
            for (int k = 0; k <= order; ++k)
                write_number(OUT + (size_t)(i * (order + 1) + k) * width, width,
                             w.X[(size_t)i * w.S + k]);
    }
    ws_clear(&w);
    return status;
}

/* ------------------------------------------------------------------ the loop */
/* |x|_inf of column k of the state rows into m */
static void state_norm(ws_t *w, int k, mpfr_ptr m)
{
    mpfr_set_zero(m, 1);
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i)
        if (mpfr_cmpabs(A(i, k), m) > 0) mpfr_abs(m, A(i, k), MPFR_RNDN);
}

/* y(t + s) of the step's polynomial (Horner), state i into out */
static void taylor_eval(ws_t *w, int p, mpfr_srcptr s, int i, mpfr_ptr out)
{
    mpfr_set(out, A(i, p), MPFR_RNDN);
    for (int k = p - 1; k >= 0; --k) {
        mpfr_mul(out, out, s, MPFR_RNDN);
        mpfr_add(out, out, A(i, k), MPFR_RNDN);
    }
}

/* Step control state: the scratch numbers of one step (at the run's precision) */
typedef struct {
    mpfr_t h, rem, xn, scale, nk, l1, l2, fixed_h;
    int have_fixed_h;
} step_t;

static void step_init(step_t *c, mpfr_prec_t prec)
{
    mpfr_inits2(prec, c->h, c->rem, c->xn, c->scale, c->nk, c->l1, c->l2, c->fixed_h,
                (mpfr_ptr)0);
    c->have_fixed_h = 0;
}

static void step_clear(step_t *c)
{
    mpfr_clears(c->h, c->rem, c->xn, c->scale, c->nk, c->l1, c->l2, c->fixed_h, (mpfr_ptr)0);
}

/* One step from (t, w->Y) towards t_end, as _Stepper._py_step: the coefficients in w, the
 * signed step in c->h, the new time in t_new, the order in *p_out. Returns 0, or -3 (step
 * size underflow). */
static int take_step(ws_t *w, step_t *c, mpfr_srcptr t, mpfr_srcptr t_end, double rtol,
                     double atol, int fixed_order, mpfr_ptr t_new, int *p_out)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE;
    mpfr_set_zero(c->xn, 1);
    for (int i = 0; i < n; ++i)
        if (mpfr_cmpabs(w->Y[i], c->xn) > 0) mpfr_abs(c->xn, w->Y[i], MPFR_RNDN);
    const int absolute = rtol * mpfr_get_d(c->xn, MPFR_RNDN) <= atol;
    if (absolute) mpfr_set_ui(c->scale, 1, MPFR_RNDN);
    else mpfr_set(c->scale, c->xn, MPFR_RNDN);
    const double eps = absolute ? atol : rtol;
    const int p = fixed_order > 0 ? fixed_order : taylor_order(eps);
    *p_out = p;
    mpfr_set(w->T0, t, MPFR_RNDN);
    taylor_coefficients(p, w);
    mpfr_sub(c->rem, t_end, t, MPFR_RNDN);
    if (c->have_fixed_h) {
        mpfr_set(c->h, c->fixed_h, MPFR_RNDN);
    } else {
        double rho = INFINITY;
        for (int k = p - 1; k <= p; ++k) {
            state_norm(w, k, c->nk);
            if (mpfr_sgn(c->nk) > 0) {
                mpfr_log(c->l1, c->scale, MPFR_RNDN);
                mpfr_log(c->l2, c->nk, MPFR_RNDN);
                mpfr_sub(c->l1, c->l1, c->l2, MPFR_RNDN);
                double r = chaplygin_exp(mpfr_get_d(c->l1, MPFR_RNDN) / k);
                if (r < rho) rho = r;
            }
        }
        double f = chaplygin_log(eps) / (p - 1);
        if (f > -2.0) f = -2.0;
        f -= 0.7 / (p - 1);
        if (isinf(rho)) mpfr_abs(c->h, c->rem, MPFR_RNDN);
        else mpfr_set_d(c->h, rho * chaplygin_exp(f), MPFR_RNDN);
    }
    const int last = mpfr_cmpabs(c->h, c->rem) >= 0;
    if (last) mpfr_set(c->h, c->rem, MPFR_RNDN);
    else if (mpfr_sgn(c->rem) < 0) mpfr_neg(c->h, c->h, MPFR_RNDN);
    if (mpfr_zero_p(c->h)) return -3;
    if (last) mpfr_set(t_new, t_end, MPFR_RNDN);
    else mpfr_add(t_new, t, c->h, MPFR_RNDN);
    return mpfr_equal_p(t_new, t) ? -3 : 0;
}

/* the largest order of a run: of the smaller tolerance, or the fixed one (0: out of range) */
static int run_order(const double *CTRL, int fixed_order)
{
    const double rtol = CTRL[0], atol = CTRL[1];
    const int p = fixed_order > 0 ? fixed_order : taylor_order(rtol < atol ? rtol : atol);
    return p < 2 || p > CHAPLYGIN_TAYLOR_MAX_ORDER ? 0 : p;
}

/* Integrate from T01 = "t0 t1" at precision prec. CTRL = {rtol, atol}; FIXED_H a number
 * ("" for the adaptive step), fixed_order > 0 fixes the order, taper != 0 lowers the
 * precision of the high orders (coefficient_prec). Output at the N_EVAL times T_EVAL (sorted
 * in the direction of integration, inside the span) into Y_EVAL (N_EVAL x n_state slots of
 * width chars), final state into Y_END (n_state slots), its time into T_REACHED (a run
 * stopped after MAX_STEPS steps resumes from them exactly). STATS = {steps, maximum order,
 * minimum order, outputs written}. Returns 0, -1 (not finite), -2 (more than MAX_STEPS
 * steps), -3 (step size underflow), -4 (no memory), -5 (a malformed number), -7 (order out
 * of range). */
int chaplygin_taylor_mpfr_run(long prec, const char *T01, const char *Y0, const char *P,
                              const double *CTRL, const char *FIXED_H, int fixed_order, int taper,
                              long n_eval, const char *T_EVAL, char *Y_EVAL, int width,
                              char *Y_END, char *T_REACHED, long max_steps, long *STATS)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE;
    const int order_ws = run_order(CTRL, fixed_order);
    if (!order_ws) return -7;
    ws_t w_;
    ws_t *w = &w_;
    if (ws_init(w, (mpfr_prec_t)prec, order_ws, taper)) return -4;
    step_t c;
    step_init(&c, (mpfr_prec_t)prec);
    mpfr_t t, t_end, t_new, s, te, ynew[CHAPLYGIN_TAYLOR_N_STATE];
    mpfr_inits2((mpfr_prec_t)prec, t, t_end, t_new, s, te, (mpfr_ptr)0);
    for (int i = 0; i < n; ++i) mpfr_init2(ynew[i], (mpfr_prec_t)prec);
    int status = read_number(&T01, t);
    if (!status) status = read_number(&T01, t_end);
    if (!status) status = read_numbers(&Y0, w->Y, n);
    if (!status) status = read_numbers(&P, w->P, CHAPLYGIN_TAYLOR_N_PARAM);
    if (!status && FIXED_H != NULL && FIXED_H[0] != '\0') {
        status = read_number(&FIXED_H, c.fixed_h);
        c.have_fixed_h = mpfr_sgn(c.fixed_h) > 0;
    }
    const int dir = mpfr_cmp(t_end, t) < 0 ? -1 : 1;
    long steps = 0, j = 0;
    int pmax = 0, pmin = CHAPLYGIN_TAYLOR_MAX_ORDER;
    const char *next_eval = T_EVAL;
    int have_te = 0;
    /* the next output time (read lazily, one token at a time) */
#define NEXT_TE() (have_te || j >= n_eval ? 0 : (have_te = !read_number(&next_eval, te), !have_te))
    if (!status && NEXT_TE()) status = -5;
    while (!status && have_te && dir * mpfr_cmp(te, t) <= 0) { /* outputs at t0 */
        for (int i = 0; i < n; ++i)
            write_number(Y_EVAL + (size_t)(j * n + i) * width, width, w->Y[i]);
        ++j;
        have_te = 0;
        if (NEXT_TE()) status = -5;
    }
    while (!status && dir * mpfr_cmp(t_end, t) > 0) {
        if (steps >= max_steps) {
            status = -2;
            break;
        }
        int p;
        status = take_step(w, &c, t, t_end, CTRL[0], CTRL[1], fixed_order, t_new, &p);
        if (status) break;
        ++steps;
        if (p > pmax) pmax = p;
        if (p < pmin) pmin = p;
        while (!status && have_te && dir * mpfr_cmp(te, t_new) <= 0) { /* outputs inside */
            mpfr_sub(s, te, t, MPFR_RNDN);
            for (int i = 0; i < n; ++i) {
                taylor_eval(w, p, s, i, ynew[i]);
                write_number(Y_EVAL + (size_t)(j * n + i) * width, width, ynew[i]);
            }
            ++j;
            have_te = 0;
            if (NEXT_TE()) status = -5;
        }
        for (int i = 0; i < n; ++i) {
            taylor_eval(w, p, c.h, i, ynew[i]);
            if (!mpfr_number_p(ynew[i])) status = status ? status : -1;
        }
        for (int i = 0; i < n; ++i) mpfr_set(w->Y[i], ynew[i], MPFR_RNDN);
        mpfr_set(t, t_new, MPFR_RNDN);
    }
#undef NEXT_TE
    for (int i = 0; i < n; ++i) write_number(Y_END + (size_t)i * width, width, w->Y[i]);
    write_number(T_REACHED, width, t);
    STATS[0] = steps;
    STATS[1] = steps ? pmax : 0;
    STATS[2] = steps ? pmin : 0;
    STATS[3] = j;
    mpfr_clears(t, t_end, t_new, s, te, (mpfr_ptr)0);
    for (int i = 0; i < n; ++i) mpfr_clear(ynew[i]);
    step_clear(&c);
    ws_clear(w);
    return status;
}

/* ------------------------------------------------------------------ one step at a time */
/* A stepper (for event location outside C): its work space, allocated once, at precision
 * prec for the orders of CTRL/fixed_order. NULL without memory or with an order out of
 * range. */
typedef struct {
    ws_t w;
    step_t c;
    mpfr_t t, t_end, t_new;
    mpfr_prec_t prec;
} stepper_t;

void *chaplygin_taylor_mpfr_stepper_new(long prec, const double *CTRL, int fixed_order,
                                        int taper)
{
    const int order_ws = run_order(CTRL, fixed_order);
    if (!order_ws) return NULL;
    stepper_t *st = malloc(sizeof(stepper_t));
    if (st == NULL) return NULL;
    if (ws_init(&st->w, (mpfr_prec_t)prec, order_ws, taper)) {
        free(st);
        return NULL;
    }
    step_init(&st->c, (mpfr_prec_t)prec);
    mpfr_inits2((mpfr_prec_t)prec, st->t, st->t_end, st->t_new, (mpfr_ptr)0);
    st->prec = (mpfr_prec_t)prec;
    return st;
}

void chaplygin_taylor_mpfr_stepper_free(void *ST)
{
    stepper_t *st = ST;
    if (st == NULL) return;
    mpfr_clears(st->t, st->t_end, st->t_new, (mpfr_ptr)0);
    step_clear(&st->c);
    ws_clear(&st->w);
    free(st);
}

/* One step of the stepper from TY = "t y..." towards T_END, the parameters P, as one step of
 * chaplygin_taylor_mpfr_run (CTRL, FIXED_H, fixed_order as there). TY_OUT receives the new
 * time and state (n_state + 1 slots of width chars), COEFFS the step's state coefficients
 * (n_state x (ORDER + 1) slots, row-major; room for the largest order of the stepper), H the
 * step taken. Returns 0, -1 (not finite), -3 (step size underflow), -5 (a malformed number). */
int chaplygin_taylor_mpfr_step(void *ST, const char *TY, const char *P, const double *CTRL,
                               const char *FIXED_H, int fixed_order, const char *T_END,
                               char *TY_OUT, char *COEFFS, char *H, int *ORDER, int width)
{
    stepper_t *st = ST;
    ws_t *w = &st->w;
    const int n = CHAPLYGIN_TAYLOR_N_STATE;
    int status = read_number(&TY, st->t);
    if (!status) status = read_numbers(&TY, w->Y, n);
    if (!status) status = read_numbers(&P, w->P, CHAPLYGIN_TAYLOR_N_PARAM);
    if (!status) status = read_number(&T_END, st->t_end);
    st->c.have_fixed_h = 0;
    if (!status && FIXED_H != NULL && FIXED_H[0] != '\0') {
        status = read_number(&FIXED_H, st->c.fixed_h);
        st->c.have_fixed_h = mpfr_sgn(st->c.fixed_h) > 0;
    }
    if (status) return status;
    int p;
    status = take_step(w, &st->c, st->t, st->t_end, CTRL[0], CTRL[1], fixed_order, st->t_new,
                       &p);
    *ORDER = p;
    write_number(H, width, st->c.h);
    if (status) return status;
    for (int i = 0; i < n; ++i)
        for (int k = 0; k <= p; ++k)
            write_number(COEFFS + (size_t)(i * (p + 1) + k) * width, width, A(i, k));
    write_number(TY_OUT, width, st->t_new);
    for (int i = 0; i < n; ++i) {
        taylor_eval(w, p, st->c.h, i, st->c.nk);
        if (!mpfr_number_p(st->c.nk)) status = -1;
        write_number(TY_OUT + (size_t)(i + 1) * width, width, st->c.nk);
    }
    return status;
}
