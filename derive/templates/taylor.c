/*
{{HEADER}}
*/
/* Taylor integrator of one chaplygin model (emitted by chaplygin.derive.emit.taylor).
 *
 * REAL is double, IEEE binary128 __float128 (libquadmath) when compiled with
 * -DCHAPLYGIN_TAYLOR_QUAD, double-double with -DCHAPLYGIN_TAYLOR_DD or quad-double with
 * -DCHAPLYGIN_TAYLOR_QD; arithmetic on REAL goes through the R_* macros (the C operators for
 * double and __float128). Every REAL crosses the interface through a pointer (cffi does not
 * know __float128), so the same declarations serve every build.
 *
 *   chaplygin_taylor_coefficients(order, T0, Y, P, OUT)   OUT[i*(order+1)+k] = y_i^(k)(t0)/k!
 *   chaplygin_taylor_step(TY, P, CTRL, T_END, COEFFS, H, ORDER)   one adaptive step
 *   chaplygin_taylor_run(...)                              the whole loop, dense output
 *                                                          (compensated state update)
 *
 * Order and step (Jorba & Zou 2005): with eps = atol if rtol |y|_inf <= atol (absolute
 * control, scale 1) else eps = rtol (relative control, scale |y|_inf), the order is
 * p = ceil(-ln(eps)/2 + 1) and the step h = rho e^-2 e^(-0.7/(p-1)) with
 * rho = min((scale/|y_[p-1]|)^(1/(p-1)), (scale/|y_[p]|)^(1/p)).
 */
#include "detmath.h" /* chaplygin/arith/templates/detmath.h, inlined when compiled */
#if defined(CHAPLYGIN_TAYLOR_DD) || defined(CHAPLYGIN_TAYLOR_QD)
#include <math.h>
/* Error-free transformations of doubles (Knuth's TwoSum, Dekker's splitting product; no FMA
 * contraction: the build uses -ffp-contract=off): a op b = result + *err exactly. */
static inline double md_two_sum(double a, double b, double *err)
{
    double s = a + b, bb = s - a;
    *err = (a - (s - bb)) + (b - bb);
    return s;
}
static inline double md_quick_two_sum(double a, double b, double *err) /* |a| >= |b| */
{
    double s = a + b;
    *err = b - (s - a);
    return s;
}
static inline double md_two_prod(double a, double b, double *err)
{
#if defined(__FMA__) || defined(__ARM_FEATURE_FMA) /* hardware fused multiply-add: the same
                                                      exact error, faster */
    double p = a * b;
    *err = __builtin_fma(a, b, -p);
    return p;
#else
    const double split = 134217729.0; /* 2^27 + 1 */
    double p = a * b, t = split * a, ah = t - (t - a), al = a - ah;
    t = split * b;
    double bh = t - (t - b), bl = b - bh;
    *err = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    return p;
#endif
}
#endif
#if defined(CHAPLYGIN_TAYLOR_DD)
#include <quadmath.h>
/* Double-double: the unevaluated sum hi + lo of two doubles, |lo| <= ulp(hi)/2 (106-bit
 * significand, about 32 digits), in the accurate ("IEEE") variants of Hida, Li and Bailey's
 * QD library (relative error of + - * / a few 2^-106). Transcendental functions (once per
 * step, at order 0) go through libquadmath: hi + lo is rounded to binary128 (113 bits), the
 * function is evaluated there and the result split back, so their error is also a few
 * 2^-106. */
typedef struct { double hi, lo; } REAL;
static inline REAL dd_make(double hi, double lo) { REAL r = {hi, lo}; return r; }
static inline REAL dd_add(REAL a, REAL b)
{
    double s2, t2, s1 = md_two_sum(a.hi, b.hi, &s2), t1 = md_two_sum(a.lo, b.lo, &t2);
    s2 += t1;
    s1 = md_quick_two_sum(s1, s2, &s2);
    s2 += t2;
    s1 = md_quick_two_sum(s1, s2, &s2);
    return dd_make(s1, s2);
}
static inline REAL dd_neg(REAL a) { return dd_make(-a.hi, -a.lo); }
static inline REAL dd_sub(REAL a, REAL b) { return dd_add(a, dd_neg(b)); }
static inline REAL dd_mul(REAL a, REAL b)
{
    double p2, p1 = md_two_prod(a.hi, b.hi, &p2);
    p2 += a.hi * b.lo + a.lo * b.hi;
    p1 = md_quick_two_sum(p1, p2, &p2);
    return dd_make(p1, p2);
}
static inline REAL dd_div(REAL a, REAL b)
{
    double q1 = a.hi / b.hi;
    REAL r = dd_sub(a, dd_mul(b, dd_make(q1, 0.0)));
    double q2 = r.hi / b.hi;
    r = dd_sub(r, dd_mul(b, dd_make(q2, 0.0)));
    double q3 = r.hi / b.hi;
    q1 = md_quick_two_sum(q1, q2, &q2);
    return dd_add(dd_make(q1, q2), dd_make(q3, 0.0));
}
static inline int dd_lt(REAL a, REAL b) { return a.hi < b.hi || (a.hi == b.hi && a.lo < b.lo); }
static inline int dd_le(REAL a, REAL b) { return a.hi < b.hi || (a.hi == b.hi && a.lo <= b.lo); }
static inline REAL dd_fabs(REAL a) { return a.hi < 0 ? dd_neg(a) : a; }
static inline __float128 dd_to_q(REAL a) { return (__float128)a.hi + (__float128)a.lo; }
static inline REAL dd_from_q(__float128 q)
{
    double hi = (double)q;
    return dd_make(hi, (double)(q - (__float128)hi));
}
static inline REAL dd_sqrt(REAL a) { return dd_from_q(sqrtq(dd_to_q(a))); }
static inline REAL dd_exp(REAL a) { return dd_from_q(expq(dd_to_q(a))); }
static inline REAL dd_sin(REAL a) { return dd_from_q(sinq(dd_to_q(a))); }
static inline REAL dd_cos(REAL a) { return dd_from_q(cosq(dd_to_q(a))); }
static inline REAL dd_pow(REAL a, REAL b) { return dd_from_q(powq(dd_to_q(a), dd_to_q(b))); }
#define R_ADD(a, b) dd_add((a), (b))
#define R_SUB(a, b) dd_sub((a), (b))
#define R_MUL(a, b) dd_mul((a), (b))
#define R_DIV(a, b) dd_div((a), (b))
#define R_NEG(a) dd_neg(a)
#define R_INT(i) dd_make((double)(i), 0.0)
#define R_DIV_INT(a, i) dd_div((a), R_INT(i))
#define R_FROM_DOUBLE(d) dd_make((d), 0.0)
#define R_TO_DOUBLE(a) ((a).hi + (a).lo)
#define R_LT(a, b) dd_lt((a), (b))
#define R_LE(a, b) dd_le((a), (b))
#define R_EQ(a, b) ((a).hi == (b).hi && (a).lo == (b).lo)
#define R_LOG_D(a) chaplygin_log((a).hi)
#define R_SQRT dd_sqrt
#define R_EXP dd_exp
#define R_SIN dd_sin
#define R_COS dd_cos
#define R_POW dd_pow
#define R_FABS dd_fabs
#define R_PI dd_from_q(M_PIq)
#define R_ISFINITE(x) (isfinite((x).hi) && isfinite((x).lo))
#elif defined(CHAPLYGIN_TAYLOR_QD)
/* Quad-double: the unevaluated sum of four doubles, each at most half an ulp of the one
 * before (212-bit significand, about 64 digits), with the algorithms of Hida, Li and Bailey
 * (QD library, "sloppy" add and multiply: relative error a few 2^-209 of the operands; the
 * division is the accurate one). sqrt by Newton's iteration, exp by argument reduction
 * (k ln 2, then 2^-10) and its series, log by Newton on exp, sin and cos by reduction modulo
 * pi/2 and their series: the transcendental functions are evaluated once per step (order 0),
 * to about 2^-200 for arguments below 1e6. */
typedef struct { double x[4]; } REAL;
static inline REAL qd_make(double a, double b, double c, double d)
{
    REAL r = {{a, b, c, d}};
    return r;
}
static inline void qd_three_sum(double *a, double *b, double *c)
{
    double t2, t3, t1 = md_two_sum(*a, *b, &t2);
    *a = md_two_sum(*c, t1, &t3);
    *b = md_two_sum(t2, t3, c);
}
static inline void qd_three_sum2(double *a, double *b, double *c)
{
    double t2, t3, t1 = md_two_sum(*a, *b, &t2);
    *a = md_two_sum(*c, t1, &t3);
    *b = t2 + t3;
}
static inline REAL qd_renorm(double c0, double c1, double c2, double c3, double c4)
{
    double s0, s1, s2 = 0.0, s3 = 0.0;
    if (!isfinite(c0)) return qd_make(c0, c1, c2, c3);
    s0 = md_quick_two_sum(c3, c4, &c4);
    s0 = md_quick_two_sum(c2, s0, &c3);
    s0 = md_quick_two_sum(c1, s0, &c2);
    c0 = md_quick_two_sum(c0, s0, &c1);
    s0 = c0;
    s1 = c1;
    if (s1 != 0.0) {
        s1 = md_quick_two_sum(s1, c2, &s2);
        if (s2 != 0.0) {
            s2 = md_quick_two_sum(s2, c3, &s3);
            if (s3 != 0.0) s3 += c4;
            else s2 += c4;
        } else {
            s1 = md_quick_two_sum(s1, c3, &s2);
            if (s2 != 0.0) s2 = md_quick_two_sum(s2, c4, &s3);
            else s1 = md_quick_two_sum(s1, c4, &s2);
        }
    } else {
        s0 = md_quick_two_sum(s0, c2, &s1);
        if (s1 != 0.0) {
            s1 = md_quick_two_sum(s1, c3, &s2);
            if (s2 != 0.0) s2 = md_quick_two_sum(s2, c4, &s3);
            else s1 = md_quick_two_sum(s1, c4, &s2);
        } else {
            s0 = md_quick_two_sum(s0, c3, &s1);
            if (s1 != 0.0) s1 = md_quick_two_sum(s1, c4, &s2);
            else s0 = md_quick_two_sum(s0, c4, &s1);
        }
    }
    return qd_make(s0, s1, s2, s3);
}
static inline REAL qd_add(REAL a, REAL b)
{
    double t0, t1, t2, t3;
    double s0 = md_two_sum(a.x[0], b.x[0], &t0);
    double s1 = md_two_sum(a.x[1], b.x[1], &t1);
    double s2 = md_two_sum(a.x[2], b.x[2], &t2);
    double s3 = md_two_sum(a.x[3], b.x[3], &t3);
    s1 = md_two_sum(s1, t0, &t0);
    qd_three_sum(&s2, &t0, &t1);
    qd_three_sum2(&s3, &t0, &t2);
    t0 = t0 + t1 + t3;
    return qd_renorm(s0, s1, s2, s3, t0);
}
static inline REAL qd_neg(REAL a) { return qd_make(-a.x[0], -a.x[1], -a.x[2], -a.x[3]); }
static inline REAL qd_sub(REAL a, REAL b) { return qd_add(a, qd_neg(b)); }
static inline REAL qd_mul(REAL a, REAL b)
{
    double q0, q1, q2, q3, q4, q5, t0, t1;
    double p0 = md_two_prod(a.x[0], b.x[0], &q0);
    double p1 = md_two_prod(a.x[0], b.x[1], &q1);
    double p2 = md_two_prod(a.x[1], b.x[0], &q2);
    double p3 = md_two_prod(a.x[0], b.x[2], &q3);
    double p4 = md_two_prod(a.x[1], b.x[1], &q4);
    double p5 = md_two_prod(a.x[2], b.x[0], &q5);
    qd_three_sum(&p1, &p2, &q0);
    qd_three_sum(&p2, &q1, &q2);
    qd_three_sum(&p3, &p4, &p5);
    double s0 = md_two_sum(p2, p3, &t0);
    double s1 = md_two_sum(q1, p4, &t1);
    double s2 = q2 + p5;
    s1 = md_two_sum(s1, t0, &t0);
    s2 += (t0 + t1);
    s1 += a.x[0] * b.x[3] + a.x[1] * b.x[2] + a.x[2] * b.x[1] + a.x[3] * b.x[0] + q0 + q3 + q4
          + q5;
    return qd_renorm(p0, p1, s0, s1, s2);
}
static inline REAL qd_from_double(double d) { return qd_make(d, 0.0, 0.0, 0.0); }
static inline REAL qd_div(REAL a, REAL b)
{
    double q0 = a.x[0] / b.x[0];
    REAL r = qd_sub(a, qd_mul(b, qd_from_double(q0)));
    double q1 = r.x[0] / b.x[0];
    r = qd_sub(r, qd_mul(b, qd_from_double(q1)));
    double q2 = r.x[0] / b.x[0];
    r = qd_sub(r, qd_mul(b, qd_from_double(q2)));
    double q3 = r.x[0] / b.x[0];
    r = qd_sub(r, qd_mul(b, qd_from_double(q3)));
    double q4 = r.x[0] / b.x[0];
    return qd_renorm(q0, q1, q2, q3, q4);
}
static inline int qd_lt(REAL a, REAL b)
{
    for (int i = 0; i < 4; ++i)
        if (a.x[i] != b.x[i]) return a.x[i] < b.x[i];
    return 0;
}
static inline int qd_eq(REAL a, REAL b)
{
    return a.x[0] == b.x[0] && a.x[1] == b.x[1] && a.x[2] == b.x[2] && a.x[3] == b.x[3];
}
static inline REAL qd_fabs(REAL a) { return a.x[0] < 0 ? qd_neg(a) : a; }
static inline REAL qd_ldexp(REAL a, int e)
{
    return qd_make(ldexp(a.x[0], e), ldexp(a.x[1], e), ldexp(a.x[2], e), ldexp(a.x[3], e));
}
#define QD_PI qd_make(0x1.921fb54442d18p+1, 0x1.1a62633145c07p-53, -0x1.f1976b7ed8fbcp-109, \
                      0x1.4cf98e804177dp-163)
#define QD_PI_2 qd_make(0x1.921fb54442d18p+0, 0x1.1a62633145c07p-54, -0x1.f1976b7ed8fbcp-110, \
                        0x1.4cf98e804177dp-164)
#define QD_LN2 qd_make(0x1.62e42fefa39efp-1, 0x1.abc9e3b39803fp-56, 0x1.7b57a079a1934p-111, \
                       -0x1.ace93a4ebe5d1p-165)
static REAL qd_sqrt(REAL a)
{
    if (a.x[0] <= 0) return qd_from_double(a.x[0] == 0 ? 0.0 : NAN);
    REAL x = qd_from_double(sqrt(a.x[0]));
    for (int i = 0; i < 3; ++i) /* Newton: 53 -> 106 -> 212 bits, one more for the rounding */
        x = qd_mul(qd_from_double(0.5), qd_add(x, qd_div(a, x)));
    return x;
}
static REAL qd_exp(REAL a)
{
    if (a.x[0] > 709.0) return qd_from_double(INFINITY);
    if (a.x[0] < -745.0) return qd_from_double(0.0);
    double k = nearbyint(a.x[0] / 0.69314718055994530942);
    /* r = (a - k ln 2) / 2^10, |r| <= 3.4e-4: exp(r) - 1 by its series to 2^-220 */
    REAL r = qd_ldexp(qd_sub(a, qd_mul(QD_LN2, qd_from_double(k))), -10);
    REAL term = r, s = r;
    for (int n = 2; n < 24; ++n) {
        term = qd_div(qd_mul(term, r), qd_from_double(n));
        s = qd_add(s, term);
        if (fabs(term.x[0]) < 1e-70 * fabs(s.x[0])) break;
    }
    for (int i = 0; i < 10; ++i) s = qd_add(qd_ldexp(s, 1), qd_mul(s, s)); /* e^2r - 1 */
    return qd_ldexp(qd_add(s, qd_from_double(1.0)), (int)k);
}
static REAL qd_log(REAL a)
{
    if (a.x[0] <= 0) return qd_from_double(a.x[0] == 0 ? -INFINITY : NAN);
    REAL y = qd_from_double(chaplygin_log(a.x[0]));
    for (int i = 0; i < 3; ++i) /* Newton on exp(y) = a: y + a exp(-y) - 1 */
        y = qd_sub(qd_add(y, qd_mul(a, qd_exp(qd_neg(y)))), qd_from_double(1.0));
    return y;
}
static REAL qd_pow(REAL a, REAL b) { return qd_exp(qd_mul(b, qd_log(a))); }
/* sin and cos of a: reduced by k pi/2, the series of sin r and cos r (|r| <= pi/4) */
static void qd_sincos(REAL a, REAL *sin_a, REAL *cos_a)
{
    double k = nearbyint(a.x[0] / 1.57079632679489661923);
    REAL r = qd_sub(a, qd_mul(QD_PI_2, qd_from_double(k)));
    REAL r2 = qd_mul(r, r), term = r, s = r, c = qd_from_double(1.0), cterm = c;
    for (int n = 1; n < 40; ++n) {
        cterm = qd_neg(qd_div(qd_mul(cterm, r2), qd_from_double((2.0 * n - 1) * (2.0 * n))));
        c = qd_add(c, cterm);
        term = qd_neg(qd_div(qd_mul(term, r2), qd_from_double((2.0 * n) * (2.0 * n + 1))));
        s = qd_add(s, term);
        if (fabs(cterm.x[0]) < 1e-70 && fabs(term.x[0]) < 1e-70) break;
    }
    long q = ((long)fmod(k, 4.0) + 4) % 4;
    REAL sv = q == 0 ? s : q == 1 ? c : q == 2 ? qd_neg(s) : qd_neg(c);
    REAL cv = q == 0 ? c : q == 1 ? qd_neg(s) : q == 2 ? qd_neg(c) : s;
    *sin_a = sv;
    *cos_a = cv;
}
static REAL qd_sin(REAL a)
{
    REAL s, c;
    qd_sincos(a, &s, &c);
    return s;
}
static REAL qd_cos(REAL a)
{
    REAL s, c;
    qd_sincos(a, &s, &c);
    return c;
}
#define R_ADD(a, b) qd_add((a), (b))
#define R_SUB(a, b) qd_sub((a), (b))
#define R_MUL(a, b) qd_mul((a), (b))
#define R_DIV(a, b) qd_div((a), (b))
#define R_NEG(a) qd_neg(a)
#define R_INT(i) qd_from_double((double)(i))
#define R_DIV_INT(a, i) qd_div((a), R_INT(i))
#define R_FROM_DOUBLE(d) qd_from_double(d)
#define R_TO_DOUBLE(a) ((a).x[0] + (a).x[1])
#define R_LT(a, b) qd_lt((a), (b))
#define R_LE(a, b) (!qd_lt((b), (a)))
#define R_EQ(a, b) qd_eq((a), (b))
#define R_LOG_D(a) chaplygin_log((a).x[0])
#define R_SQRT qd_sqrt
#define R_EXP qd_exp
#define R_SIN qd_sin
#define R_COS qd_cos
#define R_POW qd_pow
#define R_FABS qd_fabs
#define R_PI QD_PI
#define R_ISFINITE(v) (isfinite((v).x[0]) && isfinite((v).x[1]) && isfinite((v).x[2]) \
                       && isfinite((v).x[3]))
#elif defined(CHAPLYGIN_TAYLOR_QUAD)
#include <quadmath.h>
typedef __float128 REAL;
#define R_SQRT sqrtq
#define R_EXP expq
#define R_SIN sinq
#define R_COS cosq
#define R_POW powq
#define R_FABS fabsq
#define R_LOG logq
/* ln a as a double; libquadmath only where a is outside the normal doubles */
#define R_LOG_D(a) ((a) > 1e-300Q && (a) < 1e300Q ? chaplygin_log((double)(a)) : (double)logq(a))
#define R_PI M_PIq
#define R_ISFINITE(x) (finiteq(x))
#else
#include <math.h>
typedef double REAL;
#define R_SQRT sqrt
#define R_EXP chaplygin_exp
#define R_SIN chaplygin_sin
#define R_COS chaplygin_cos
#define R_POW chaplygin_pow
#define R_FABS fabs
#define R_LOG chaplygin_log
#define R_LOG_D(a) chaplygin_log(a)
#define R_PI 3.14159265358979323846264338327950288
#define R_ISFINITE(x) (isfinite(x))
#endif
#ifndef R_ADD /* double and __float128: the C operators */
#define R_OPERATORS 1
#define R_ADD(a, b) ((a) + (b))
#define R_SUB(a, b) ((a) - (b))
#define R_MUL(a, b) ((a) * (b))
#define R_DIV(a, b) ((a) / (b))
#define R_NEG(a) (-(a))
#define R_INT(i) ((REAL)(i))
/* a / i for a positive integer i: times the reciprocal (a constant where i is one), one
 * rounding more than the division and much cheaper (issue 26 allows the change) */
#define R_DIV_INT(a, i) ((a) * ((REAL)1 / (REAL)(i)))
#define R_FROM_DOUBLE(d) ((REAL)(d))
#define R_TO_DOUBLE(a) ((double)(a))
#define R_LT(a, b) ((a) < (b))
#define R_LE(a, b) ((a) <= (b))
#define R_EQ(a, b) ((a) == (b))
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
/* Convolutions sum the terms of the coefficients known before order k first (j = 1 .. k-1, in
 * increasing j), then add the two terms that involve the order-k coefficients just computed:
 * the long sums do not wait for this order, which keeps the chain from one order to the next
 * short. derive/emit/taylor_unroll.py writes the same sums out for a fixed order: keep the two in
 * the same order of operations (the unrolled code is bit-identical to this one). */

/* c = a b: c_k = sum_{j=1..k-1} a_j b_{k-j} + (a_0 b_k + a_k b_0) (k >= 1) */
static inline REAL tc_mul(const REAL *restrict a, const REAL *restrict b, int k)
{
    REAL last = R_ADD(R_MUL(a[0], b[k]), R_MUL(a[k], b[0]));
    if (k < 2) return last;
    REAL s = R_MUL(a[1], b[k - 1]);
    for (int j = 2; j < k; ++j) s = R_ADD(s, R_MUL(a[j], b[k - j]));
    return R_ADD(s, last);
}

/* c = a^2: c_k = 2 (sum_{1 <= j < k-j} a_j a_{k-j} + a_0 a_k) [+ a_{k/2}^2] (k >= 1) */
static inline REAL tc_sq(const REAL *restrict a, int k)
{
    REAL s = R_MUL(a[0], a[k]);
    if (k >= 3) {
        REAL o = R_MUL(a[1], a[k - 1]);
        for (int j = 2; j < (k + 1) / 2; ++j) o = R_ADD(o, R_MUL(a[j], a[k - j]));
        s = R_ADD(o, s);
    }
    s = R_ADD(s, s);
    if (k % 2 == 0) s = R_ADD(s, R_MUL(a[k / 2], a[k / 2]));
    return s;
}

/* c = a / b: c_k = ((a_k - b_k c_0) - sum_{j=1..k-1} b_j c_{k-j}) r (k >= 1), r = 1/b_0
 * worked out once per step (a product instead of a division on every order's chain) */
static inline REAL tc_div(REAL ak, const REAL *restrict b, const REAL *restrict c, REAL r,
                          int k)
{
    REAL last = R_SUB(ak, R_MUL(b[k], c[0]));
    if (k < 2) return R_MUL(last, r);
    REAL s = R_MUL(b[1], c[k - 1]);
    for (int j = 2; j < k; ++j) s = R_ADD(s, R_MUL(b[j], c[k - j]));
    return R_MUL(R_SUB(last, s), r);
}

/* c = sqrt(a): c_k = (a_k - sum_{j=1..k-1} c_j c_{k-j}) / (2 c_0) */
static inline REAL tc_sqrt(const REAL *restrict a, const REAL *restrict c, int k)
{
    REAL s = a[k];
    for (int j = 1; j < k; ++j) s = R_SUB(s, R_MUL(c[j], c[k - j]));
    return R_DIV(s, R_MUL(R_INT(2), c[0]));
}

/* c = a^(p/q): c_k = sum_{j<k} (p (k-j) - q j) a_{k-j} c_j / (q k a_0) */
static inline REAL tc_pow(const REAL *restrict a, const REAL *restrict c, int p, int q, int k)
{
    REAL s = R_INT(0);
    for (int j = 0; j < k; ++j)
        s = R_ADD(s, R_MUL(R_MUL(R_INT(p * (k - j) - q * j), a[k - j]), c[j]));
    return R_DIV(s, R_MUL(R_MUL(R_INT(q), R_INT(k)), a[0]));
}

/* c = exp(a) (c itself), or the sin/cos pair (c the partner): sum_{j=1..k} j a_j c_{k-j} / k */
static inline REAL tc_exp(const REAL *restrict a, const REAL *restrict c, int k)
{
    REAL s = R_INT(0);
    for (int j = 1; j <= k; ++j) s = R_ADD(s, R_MUL(R_MUL(R_INT(j), a[j]), c[k - j]));
    return R_DIV_INT(s, k);
}

{{COEFFICIENTS}}

/* chaplygin: the coefficients written out for fixed orders go here */
#ifndef TAYLOR_COEFFICIENTS
#define TAYLOR_COEFFICIENTS taylor_coefficients
#endif

void chaplygin_taylor_coefficients(int order, const REAL *T0, const REAL *Y, const REAL *P,
                                   REAL *OUT)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE, S = order + 1;
    REAL *X = malloc(sizeof(REAL) * (size_t)S * CHAPLYGIN_TAYLOR_N_NODES);
    if (X == NULL) return;
    TAYLOR_COEFFICIENTS(order, *T0, Y, P, X);
    for (int i = 0; i < n * S; ++i) OUT[i] = X[i];
    free(X);
}

/* ------------------------------------------------------------------ step control */
static int taylor_order(double eps)
{
    int p = (int)ceil(-0.5 * chaplygin_log(eps) + 1.0);
    if (p < 2) p = 2;
    if (p > CHAPLYGIN_TAYLOR_MAX_ORDER) p = CHAPLYGIN_TAYLOR_MAX_ORDER;
    return p;
}

/* What the step control needs from ctrl = {rtol, atol, fixed_h}, worked out once per run: the
 * order and the safety factor e^-2 e^(-0.7/(p-1)) under relative [0] and absolute [1] control
 * (fixed_order > 0 forces the order). */
typedef struct {
    REAL rtol, atol, fixed_h;
    int order[2];
    double safety[2];
} taylor_control;

static taylor_control taylor_control_of(const REAL *restrict ctrl, int fixed_order)
{
    taylor_control c;
    c.rtol = ctrl[0];
    c.atol = ctrl[1];
    c.fixed_h = ctrl[2];
    for (int a = 0; a < 2; ++a) {
        int p = fixed_order > 0 ? fixed_order : taylor_order(R_TO_DOUBLE(ctrl[a]));
        c.order[a] = p;
        c.safety[a] = chaplygin_exp(-2.0) * chaplygin_exp(-0.7 / (p - 1));
    }
    return c;
}

static REAL inf_norm(const REAL *restrict X, int S, int k)
{
    REAL m = R_INT(0);
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i) {
        REAL v = R_FABS(X[i * S + k]);
        if (R_LT(m, v)) m = v;
    }
    return m;
}

/* Coefficients at (t, y) in X (stride order+1); returns the step (signed, capped at t_end).
 * fixed_h > 0 forces the step. rho = min((scale/|y_[p-1]|)^(1/(p-1)), (scale/|y_[p]|)^(1/p))
 * is taken in logarithms (one exp); logs in double: rho needs a few digits only. */
static REAL taylor_step_size(REAL t, const REAL *restrict y, const REAL *restrict P,
                             const taylor_control *restrict c, REAL t_end, REAL *restrict X,
                             int *order_out)
{
    REAL xn = R_INT(0);
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i)
        if (R_LT(xn, R_FABS(y[i]))) xn = R_FABS(y[i]);
    const int absolute = R_LE(R_MUL(c->rtol, xn), c->atol);
    const int p = c->order[absolute];
    *order_out = p;
    const int S = p + 1;
    TAYLOR_COEFFICIENTS(p, t, y, P, X);
    REAL remaining = R_SUB(t_end, t);
    REAL dir = R_LT(remaining, R_INT(0)) ? R_INT(-1) : R_INT(1);
    REAL h;
    if (R_LT(R_INT(0), c->fixed_h)) {
        h = c->fixed_h;
    } else {
        double e = INFINITY;
        const double log_scale = absolute ? 0.0 : R_LOG_D(xn);
        REAL n1 = inf_norm(X, S, p - 1), n2 = inf_norm(X, S, p);
        if (R_LT(R_INT(0), n1)) {
            double r = (log_scale - R_LOG_D(n1)) / (p - 1);
            if (r < e) e = r;
        }
        if (R_LT(R_INT(0), n2)) {
            double r = (log_scale - R_LOG_D(n2)) / p;
            if (r < e) e = r;
        }
        double rho = chaplygin_exp(e);
        if (isinf(rho)) h = R_FABS(remaining);
        else h = R_FROM_DOUBLE(rho * c->safety[absolute]);
    }
    if (R_LE(R_FABS(remaining), h)) return remaining;
    return R_MUL(dir, h);
}

/* y(t + s) from the Taylor polynomial of the state coefficients in X (Horner). */
static void taylor_eval(const REAL *restrict X, int p, REAL s, REAL *restrict out)
{
    const int S = p + 1;
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i) {
        const REAL *c = X + i * S;
        REAL v = c[p];
        for (int k = p - 1; k >= 0; --k) v = R_ADD(R_MUL(v, s), c[k]);
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
    const taylor_control c = taylor_control_of(CTRL, fixed_order);
    REAL h = taylor_step_size(t, TY + 1, P, &c, *T_END, X, &p);
    for (int i = 0; i < n * (p + 1); ++i) COEFFS[i] = X[i];
    REAL y[CHAPLYGIN_TAYLOR_N_STATE];
    taylor_eval(X, p, h, y);
    free(X);
    int status = 0;
    for (int i = 0; i < n; ++i) {
        if (!R_ISFINITE(y[i])) status = -1;
        TY[1 + i] = y[i];
    }
    TY[0] = R_EQ(h, R_SUB(*T_END, t)) ? *T_END : R_ADD(t, h);
    *H = h;
    *ORDER = p;
    return status;
}

/* The state update with compensation (Kahan): the state is carried as y + y_lo, y_lo the
 * rounding error of the last additions; y(t + s) = c_0 + (sum_{k>=1} c_k s^k + y_lo), and the
 * new y_lo is the exact error of that addition (TwoSum). Rounding errors of the updates then do
 * not pile up over many steps (quad, T = 50: final error 3.0e-33 -> 6.3e-34). Only for the
 * IEEE types (double, __float128), where TwoSum is exact; the multi-double types keep y_lo = 0
 * (their arithmetic already carries the extra bits). */
#ifdef R_OPERATORS
#define TAYLOR_COMPENSATED 1
#else
#define TAYLOR_COMPENSATED 0
#endif
#if TAYLOR_COMPENSATED
static void taylor_eval_compensated(const REAL *restrict X, int p, REAL s,
                                    const REAL *restrict ylo, REAL *restrict out,
                                    REAL *restrict ylo_out)
{
    const int S = p + 1;
    int i = 0;
#ifdef TAYLOR_VREAL
    /* double with the written-out coefficients (derive/emit/taylor_unroll.py): two components
     * at a time in a GNU C vector of 2 doubles, each lane the scalar loop's operations
     * below (the same bits) */
    for (; i + 1 < CHAPLYGIN_TAYLOR_N_STATE; i += 2) {
        const REAL *c = X + i * S, *e = X + (i + 1) * S;
        vreal v = {c[p], e[p]};
        for (int k = p - 1; k >= 1; --k) v = v * s + (vreal){c[k], e[k]};
        const vreal d = v * s + (vreal){ylo[i], ylo[i + 1]};
        const vreal a = {c[0], e[0]};
        const vreal y = a + d;
        if (ylo_out != NULL) {
            const vreal bb = y - a;
            const vreal lo = (a - (y - bb)) + (d - bb);
            ylo_out[i] = lo[0];
            ylo_out[i + 1] = lo[1];
        }
        out[i] = y[0];
        out[i + 1] = y[1];
    }
#endif
    for (; i < CHAPLYGIN_TAYLOR_N_STATE; ++i) {
        const REAL *c = X + i * S;
        REAL v = c[p];
        for (int k = p - 1; k >= 1; --k) v = R_ADD(R_MUL(v, s), c[k]);
        const REAL d = R_ADD(R_MUL(v, s), ylo[i]);
        const REAL y = R_ADD(c[0], d);
        if (ylo_out != NULL) {  /* TwoSum: c_0 + d = y + error exactly */
            const REAL bb = R_SUB(y, c[0]);
            ylo_out[i] = R_ADD(R_SUB(c[0], R_SUB(y, bb)), R_SUB(d, bb));
        }
        out[i] = y;
    }
}
#endif

/* Integrate from T01[0] to T01[1]. Output at the N_EVAL times T_EVAL (sorted in the direction
 * of integration, inside the span) into Y_EVAL (N_EVAL x n_state), final state in Y_END (+ its
 * compensation in Y_LO, see taylor_eval_compensated) and its time in T_REACHED: a run stopped
 * after MAX_STEPS steps resumes from them exactly. Y_LO (may be NULL: zeros) gives the
 * compensation of Y0 on entry. STATS = {steps, maximum order, minimum order, outputs
 * written}. Returns 0, -1 (not finite), -2 (more than MAX_STEPS steps), -3 (step size
 * underflow), -4 (no memory). */
int chaplygin_taylor_run(const REAL *T01, const REAL *Y0, const REAL *P, const REAL *CTRL,
                         int fixed_order, long n_eval, const REAL *T_EVAL, REAL *Y_EVAL,
                         REAL *Y_END, REAL *T_REACHED, long max_steps, long *STATS, REAL *Y_LO)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE;
    REAL *X = malloc(sizeof(REAL) * (CHAPLYGIN_TAYLOR_MAX_ORDER + 1) * CHAPLYGIN_TAYLOR_N_NODES);
    if (X == NULL) return -4;
    REAL t = T01[0];
    const REAL t_end = T01[1];
    const REAL dir = R_LT(t_end, t) ? R_INT(-1) : R_INT(1);
    const taylor_control c = taylor_control_of(CTRL, fixed_order);
    REAL y[CHAPLYGIN_TAYLOR_N_STATE], ylo[CHAPLYGIN_TAYLOR_N_STATE];
    REAL ynew[CHAPLYGIN_TAYLOR_N_STATE], ylo_new[CHAPLYGIN_TAYLOR_N_STATE];
    for (int i = 0; i < n; ++i) {
        y[i] = Y0[i];
        ylo[i] = TAYLOR_COMPENSATED && Y_LO != NULL ? Y_LO[i] : R_INT(0);
    }
    long steps = 0, j = 0;
    int pmax = 0, pmin = CHAPLYGIN_TAYLOR_MAX_ORDER, status = 0;
    while (j < n_eval && R_LE(R_MUL(dir, R_SUB(T_EVAL[j], t)), R_INT(0))) {  /* output at t0 */
        for (int i = 0; i < n; ++i)
            Y_EVAL[j * n + i] = TAYLOR_COMPENSATED ? R_ADD(y[i], ylo[i]) : y[i];
        ++j;
    }
    while (R_LT(R_INT(0), R_MUL(dir, R_SUB(t_end, t)))) {
        if (steps >= max_steps) { status = -2; break; }
        int p;
        REAL h = taylor_step_size(t, y, P, &c, t_end, X, &p);
        if (R_EQ(h, R_INT(0)) || R_EQ(R_ADD(t, h), t)) { status = -3; break; }
        if (p > pmax) pmax = p;
        if (p < pmin) pmin = p;
        int last = R_EQ(h, R_SUB(t_end, t));
        REAL t_new = last ? t_end : R_ADD(t, h);
        while (j < n_eval && R_LE(R_MUL(dir, R_SUB(T_EVAL[j], t_new)), R_INT(0))) {
#if TAYLOR_COMPENSATED
            taylor_eval_compensated(X, p, R_SUB(T_EVAL[j], t), ylo, Y_EVAL + j * n, NULL);
#else
            taylor_eval(X, p, R_SUB(T_EVAL[j], t), Y_EVAL + j * n);
#endif
            ++j;
        }
#if TAYLOR_COMPENSATED
        taylor_eval_compensated(X, p, h, ylo, ynew, ylo_new);
#else
        taylor_eval(X, p, h, ynew);
        (void)ylo_new;
#endif
        ++steps;
        for (int i = 0; i < n; ++i) {
            if (!R_ISFINITE(ynew[i])) status = -1;
            y[i] = ynew[i];
#if TAYLOR_COMPENSATED
            ylo[i] = ylo_new[i];
#endif
        }
        t = t_new;
        if (status) break;
    }
    for (int i = 0; i < n; ++i) {
        Y_END[i] = y[i];
        if (Y_LO != NULL) Y_LO[i] = ylo[i];
    }
    *T_REACHED = t;
    STATS[0] = steps;
    STATS[1] = pmax;
    STATS[2] = steps ? pmin : 0;
    STATS[3] = j;
    free(X);
    return status;
}
