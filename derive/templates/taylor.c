/*
{{HEADER}}
*/
/* Taylor integrator of one chaplygin model (emitted by chaplygin.derive.emit.taylor).
 *
 * REAL is double, or IEEE binary128 __float128 (libquadmath) when compiled with
 * -DCHAPLYGIN_TAYLOR_QUAD. Every REAL crosses the interface through a pointer (cffi does not
 * know __float128), so the same declarations serve both builds.
 *
 *   chaplygin_taylor_coefficients(order, T0, Y, P, OUT)   OUT[i*(order+1)+k] = y_i^(k)(t0)/k!
 *   chaplygin_taylor_step(TY, P, CTRL, T_END, COEFFS, H, ORDER)   one adaptive step
 *   chaplygin_taylor_run(...)                              the whole loop, dense output
 *
 * Order and step (Jorba & Zou 2005): with eps = atol if rtol |y|_inf <= atol (absolute
 * control, scale 1) else eps = rtol (relative control, scale |y|_inf), the order is
 * p = ceil(-ln(eps)/2 + 1) and the step h = rho e^-2 e^(-0.7/(p-1)) with
 * rho = min((scale/|y_[p-1]|)^(1/(p-1)), (scale/|y_[p]|)^(1/p)).
 */
#ifdef CHAPLYGIN_TAYLOR_QUAD
#include <quadmath.h>
typedef __float128 REAL;
#define R_SQRT sqrtq
#define R_EXP expq
#define R_SIN sinq
#define R_COS cosq
#define R_POW powq
#define R_FABS fabsq
#define R_LOG logq
#define R_PI M_PIq
#define R_ISFINITE(x) (finiteq(x))
#else
#include <math.h>
typedef double REAL;
#define R_SQRT sqrt
#define R_EXP exp
#define R_SIN sin
#define R_COS cos
#define R_POW pow
#define R_FABS fabs
#define R_LOG log
#define R_PI 3.14159265358979323846264338327950288
#define R_ISFINITE(x) (isfinite(x))
#endif
#include <math.h>
#include <stddef.h>
#include <stdlib.h>

#define CHAPLYGIN_TAYLOR_N_STATE {{N_STATE}}
#define CHAPLYGIN_TAYLOR_N_PARAM {{N_PARAM}}
#define CHAPLYGIN_TAYLOR_N_NODES {{N_NODES}}
#define CHAPLYGIN_TAYLOR_MAX_ORDER {{MAX_ORDER}}

const char *chaplygin_taylor_model_hash(void) { return "{{MODEL_HASH}}"; }

void chaplygin_taylor_sizes(int *OUT)
{
    OUT[0] = CHAPLYGIN_TAYLOR_N_STATE;
    OUT[1] = CHAPLYGIN_TAYLOR_N_PARAM;
    OUT[2] = CHAPLYGIN_TAYLOR_N_NODES;
    OUT[3] = CHAPLYGIN_TAYLOR_MAX_ORDER;
    OUT[4] = (int)sizeof(REAL);
}

/* ------------------------------------------------------------------ recurrences */
static inline REAL tc_mul(const REAL *restrict a, const REAL *restrict b, int k)
{
    REAL s = 0;
    for (int j = 0; j <= k; ++j) s += a[j] * b[k - j];
    return s;
}

static inline REAL tc_sq(const REAL *restrict a, int k)
{
    REAL s = 0;
    for (int j = 0; j < (k + 1) / 2; ++j) s += a[j] * a[k - j];
    s += s;
    if (k % 2 == 0) s += a[k / 2] * a[k / 2];
    return s;
}

/* c = a / b: c_k = (a_k - sum_{j=1..k} b_j c_{k-j}) / b_0 */
static inline REAL tc_div(REAL ak, const REAL *restrict b, const REAL *restrict c, int k)
{
    REAL s = ak;
    for (int j = 1; j <= k; ++j) s -= b[j] * c[k - j];
    return s / b[0];
}

/* c = sqrt(a): c_k = (a_k - sum_{j=1..k-1} c_j c_{k-j}) / (2 c_0) */
static inline REAL tc_sqrt(const REAL *restrict a, const REAL *restrict c, int k)
{
    REAL s = a[k];
    for (int j = 1; j < k; ++j) s -= c[j] * c[k - j];
    return s / (2 * c[0]);
}

/* c = a^(p/q): c_k = sum_{j<k} (p (k-j) - q j) a_{k-j} c_j / (q k a_0) */
static inline REAL tc_pow(const REAL *restrict a, const REAL *restrict c, int p, int q, int k)
{
    REAL s = 0;
    for (int j = 0; j < k; ++j) s += (REAL)(p * (k - j) - q * j) * a[k - j] * c[j];
    return s / ((REAL)q * (REAL)k * a[0]);
}

/* c = exp(a) (c itself), or the sin/cos pair (c the partner): sum_{j=1..k} j a_j c_{k-j} / k */
static inline REAL tc_exp(const REAL *restrict a, const REAL *restrict c, int k)
{
    REAL s = 0;
    for (int j = 1; j <= k; ++j) s += (REAL)j * a[j] * c[k - j];
    return s / (REAL)k;
}

{{COEFFICIENTS}}

void chaplygin_taylor_coefficients(int order, const REAL *T0, const REAL *Y, const REAL *P,
                                   REAL *OUT)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE, S = order + 1;
    REAL *X = malloc(sizeof(REAL) * (size_t)S * CHAPLYGIN_TAYLOR_N_NODES);
    if (X == NULL) return;
    taylor_coefficients(order, *T0, Y, P, X);
    for (int i = 0; i < n * S; ++i) OUT[i] = X[i];
    free(X);
}

/* ------------------------------------------------------------------ step control */
static int taylor_order(double eps)
{
    int p = (int)ceil(-0.5 * log(eps) + 1.0);
    if (p < 2) p = 2;
    if (p > CHAPLYGIN_TAYLOR_MAX_ORDER) p = CHAPLYGIN_TAYLOR_MAX_ORDER;
    return p;
}

static REAL inf_norm(const REAL *restrict X, int S, int k)
{
    REAL m = 0;
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i) {
        REAL v = R_FABS(X[i * S + k]);
        if (v > m) m = v;
    }
    return m;
}

/* Coefficients at (t, y) in X (stride order+1); returns the step (signed, capped at t_end).
 * ctrl = {rtol, atol, fixed_h}: fixed_h > 0 forces the step, fixed_order > 0 the order. */
static REAL taylor_step_size(REAL t, const REAL *restrict y, const REAL *restrict P,
                             const REAL *restrict ctrl, int fixed_order, REAL t_end,
                             REAL *restrict X, int *order_out)
{
    const REAL rtol = ctrl[0], atol = ctrl[1], fixed_h = ctrl[2];
    REAL xn = 0;
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i)
        if (R_FABS(y[i]) > xn) xn = R_FABS(y[i]);
    int absolute = rtol * xn <= atol;
    REAL scale = absolute ? (REAL)1 : xn;
    int p = fixed_order > 0 ? fixed_order : taylor_order((double)(absolute ? atol : rtol));
    *order_out = p;
    const int S = p + 1;
    taylor_coefficients(p, t, y, P, X);
    REAL remaining = t_end - t;
    REAL dir = remaining < 0 ? -1 : 1;
    REAL h;
    if (fixed_h > 0) {
        h = fixed_h;
    } else {
        double rho = INFINITY;
        REAL n1 = inf_norm(X, S, p - 1), n2 = inf_norm(X, S, p);
        if (n1 > 0) {
            double r = exp((double)(R_LOG(scale) - R_LOG(n1)) / (p - 1));
            if (r < rho) rho = r;
        }
        if (n2 > 0) {
            double r = exp((double)(R_LOG(scale) - R_LOG(n2)) / p);
            if (r < rho) rho = r;
        }
        if (isinf(rho)) h = R_FABS(remaining);
        else h = (REAL)(rho * exp(-2.0) * exp(-0.7 / (p - 1)));
    }
    if (h >= R_FABS(remaining)) return remaining;
    return dir * h;
}

/* y(t + s) from the Taylor polynomial of the state coefficients in X (Horner). */
static void taylor_eval(const REAL *restrict X, int p, REAL s, REAL *restrict out)
{
    const int S = p + 1;
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i) {
        const REAL *c = X + i * S;
        REAL v = c[p];
        for (int k = p - 1; k >= 0; --k) v = v * s + c[k];
        out[i] = v;
    }
}

/* One step. TY = {t, y...} is advanced in place; COEFFS receives the state coefficients of
 * the step (n_state x (ORDER+1), row-major), H the step taken. Returns 0, or -1 when the new
 * state is not finite. */
int chaplygin_taylor_step(REAL *TY, const REAL *P, const REAL *CTRL, int fixed_order,
                          const REAL *T_END, REAL *COEFFS, REAL *H, int *ORDER)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE;
    REAL *X = malloc(sizeof(REAL) * (CHAPLYGIN_TAYLOR_MAX_ORDER + 1) * CHAPLYGIN_TAYLOR_N_NODES);
    if (X == NULL) return -4;
    int p;
    REAL t = TY[0];
    REAL h = taylor_step_size(t, TY + 1, P, CTRL, fixed_order, *T_END, X, &p);
    for (int i = 0; i < n * (p + 1); ++i) COEFFS[i] = X[i];
    REAL y[CHAPLYGIN_TAYLOR_N_STATE];
    taylor_eval(X, p, h, y);
    free(X);
    int status = 0;
    for (int i = 0; i < n; ++i) {
        if (!R_ISFINITE(y[i])) status = -1;
        TY[1 + i] = y[i];
    }
    TY[0] = (h == *T_END - t) ? *T_END : t + h;
    *H = h;
    *ORDER = p;
    return status;
}

/* Integrate from T01[0] to T01[1]. Output at the N_EVAL times T_EVAL (sorted in the direction
 * of integration, inside the span) into Y_EVAL (N_EVAL x n_state), final state in Y_END.
 * STATS = {steps, maximum order, minimum order}. Returns 0, -1 (not finite), -2 (more than
 * MAX_STEPS steps), -3 (step size underflow), -4 (no memory). */
int chaplygin_taylor_run(const REAL *T01, const REAL *Y0, const REAL *P, const REAL *CTRL,
                         int fixed_order, long n_eval, const REAL *T_EVAL, REAL *Y_EVAL,
                         REAL *Y_END, long max_steps, long *STATS)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE;
    REAL *X = malloc(sizeof(REAL) * (CHAPLYGIN_TAYLOR_MAX_ORDER + 1) * CHAPLYGIN_TAYLOR_N_NODES);
    if (X == NULL) return -4;
    REAL t = T01[0];
    const REAL t_end = T01[1];
    const REAL dir = t_end < t ? -1 : 1;
    REAL y[CHAPLYGIN_TAYLOR_N_STATE], ynew[CHAPLYGIN_TAYLOR_N_STATE];
    for (int i = 0; i < n; ++i) y[i] = Y0[i];
    long steps = 0, j = 0;
    int pmax = 0, pmin = CHAPLYGIN_TAYLOR_MAX_ORDER, status = 0;
    while (j < n_eval && dir * (T_EVAL[j] - t) <= 0) {  /* output at t0 */
        for (int i = 0; i < n; ++i) Y_EVAL[j * n + i] = y[i];
        ++j;
    }
    while (dir * (t_end - t) > 0) {
        if (steps >= max_steps) { status = -2; break; }
        int p;
        REAL h = taylor_step_size(t, y, P, CTRL, fixed_order, t_end, X, &p);
        if (h == 0 || t + h == t) { status = -3; break; }
        if (p > pmax) pmax = p;
        if (p < pmin) pmin = p;
        int last = (h == t_end - t);
        REAL t_new = last ? t_end : t + h;
        while (j < n_eval && dir * (T_EVAL[j] - t_new) <= 0) {
            taylor_eval(X, p, T_EVAL[j] - t, Y_EVAL + j * n);
            ++j;
        }
        taylor_eval(X, p, h, ynew);
        ++steps;
        for (int i = 0; i < n; ++i) {
            if (!R_ISFINITE(ynew[i])) status = -1;
            y[i] = ynew[i];
        }
        t = t_new;
        if (status) break;
    }
    for (int i = 0; i < n; ++i) Y_END[i] = y[i];
    STATS[0] = steps;
    STATS[1] = pmax;
    STATS[2] = steps ? pmin : 0;
    STATS[3] = j;
    free(X);
    return status;
}
