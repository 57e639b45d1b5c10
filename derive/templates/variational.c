/* chaplygin.numerics.dynamics.variational: the variational equations of one model, integrated in C.
 *
 * Appended to a model's emitted C source (generated/<model>.c), whose chaplygin_rhs_jac (the
 * right-hand side and the generated Jacobian in one routine, their common subexpressions
 * computed once) it calls. The augmented state is
 *     Z = (y, V, q),  y' = f(t, y),  V' = J(t, y) V,  q' = tr J(t, y) = div f,
 * with y the state (n doubles), V an n x k matrix of tangent vectors (row-major, V[i*k + j] is
 * component i of vector j; V = identity gives the state-transition matrix Phi) and q the integral
 * of the divergence of the vector field along the orbit.
 *
 * Method: DOP853 (Dormand & Prince; Hairer, Norsett & Wanner, Solving ODEs I, II.5 and II.10),
 * adaptive, with the error estimate and step control of Hairer's dop853.f (also scipy's DOP853):
 * the error is measured on y and V (not on q, a quadrature), scale atol + rtol*max(|z|, |z_new|).
 * The tableau below is the standard one (the same numbers as scipy's dop853_coefficients).
 *
 * Routines (all return 0 on success, 1 when max_steps is exceeded, 2 when the step size
 * underflows, 3 on a non-finite value):
 *   chaplygin_var_flow          one interval [t0, t1]
 *   chaplygin_var_renormalised  n_intervals intervals of length tau, each followed by the
 *                               projection of V onto the tangent space of the integrals' level set
 *                               (optional) and a QR (modified Gram-Schmidt, twice) of V; the logs
 *                               of R's diagonal and the divergence integrals are written out.
 *   chaplygin_var_integral_gradients  d(integral_i)/dy_j by central differences (exact up to
 *                               rounding for integrals quadratic in y, as the ball's are).
 * stats: [0] accepted steps, [1] rejected steps, [2] evaluations of the augmented system,
 *        [3] the step size to start with (0: estimated), then the last step size.
 */
#include <float.h>
#include <math.h>

#define CV_N CHAPLYGIN_N_STATE
#define CV_NI (CHAPLYGIN_N_INTEGRALS > 0 ? CHAPLYGIN_N_INTEGRALS : 1)
#define CV_ZMAX (CV_N + CV_N * CV_N + 1)
#define CV_STAGES 12

static const double DOP_C[12] = {
    0.0,
    0.05260015195876773,
    0.0789002279381516,
    0.1183503419072274,
    0.2816496580927726,
    0.3333333333333333,
    0.25,
    0.3076923076923077,
    0.6512820512820513,
    0.6,
    0.8571428571428571,
    1.0
};
static const double DOP_A[144] = {
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.05260015195876773,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0197250569845379,
    0.0591751709536137,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.02958758547680685,
    0.0,
    0.08876275643042054,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.2413651341592667,
    0.0,
    -0.8845494793282861,
    0.924834003261792,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.037037037037037035,
    0.0,
    0.0,
    0.17082860872947386,
    0.12546768756682242,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.037109375,
    0.0,
    0.0,
    0.17025221101954405,
    0.06021653898045596,
    -0.017578125,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.03709200011850479,
    0.0,
    0.0,
    0.17038392571223998,
    0.10726203044637328,
    -0.015319437748624402,
    0.008273789163814023,
    0.0,
    0.0,
    0.0,
    0.0,
    0.0,
    0.6241109587160757,
    0.0,
    0.0,
    -3.3608926294469414,
    -0.868219346841726,
    27.59209969944671,
    20.154067550477894,
    -43.48988418106996,
    0.0,
    0.0,
    0.0,
    0.0,
    0.47766253643826434,
    0.0,
    0.0,
    -2.4881146199716677,
    -0.590290826836843,
    21.230051448181193,
    15.279233632882423,
    -33.28821096898486,
    -0.020331201708508627,
    0.0,
    0.0,
    0.0,
    -0.9371424300859873,
    0.0,
    0.0,
    5.186372428844064,
    1.0914373489967295,
    -8.149787010746927,
    -18.52006565999696,
    22.739487099350505,
    2.4936055526796523,
    -3.0467644718982196,
    0.0,
    0.0,
    2.273310147516538,
    0.0,
    0.0,
    -10.53449546673725,
    -2.0008720582248625,
    -17.9589318631188,
    27.94888452941996,
    -2.8589982771350235,
    -8.87285693353063,
    12.360567175794303,
    0.6433927460157636,
    0.0
};
static const double DOP_B[12] = {
    0.054293734116568765,
    0.0,
    0.0,
    0.0,
    0.0,
    4.450312892752409,
    1.8915178993145003,
    -5.801203960010585,
    0.3111643669578199,
    -0.1521609496625161,
    0.20136540080403034,
    0.04471061572777259
};
static const double DOP_E3[13] = {
    -0.18980075407240762,
    0.0,
    0.0,
    0.0,
    0.0,
    4.450312892752409,
    1.8915178993145003,
    -5.801203960010585,
    -0.4226823213237919,
    -0.1521609496625161,
    0.20136540080403034,
    0.02265179219836082,
    0.0
};
static const double DOP_E5[13] = {
    0.01312004499419488,
    0.0,
    0.0,
    0.0,
    0.0,
    -1.2251564463762044,
    -0.4957589496572502,
    1.6643771824549864,
    -0.35032884874997366,
    0.3341791187130175,
    0.08192320648511571,
    -0.022355307863886294,
    0.0
};

static void cv_f(double t, const double *z, int k, const double *P, double *out)
{
    double FJ[CV_N + CV_N * CV_N];
    const double *J = FJ + CV_N;
    const double *V = z + CV_N;
    double *dV = out + CV_N;
    chaplygin_rhs_jac(t, z, P, FJ);
    double tr = 0.0;
    for (int i = 0; i < CV_N; ++i) {
        out[i] = FJ[i];
        tr += J[i * CV_N + i];
        for (int j = 0; j < k; ++j) {
            double s = 0.0;
            for (int l = 0; l < CV_N; ++l) s += J[i * CV_N + l] * V[l * k + j];
            dV[i * k + j] = s;
        }
    }
    out[CV_N + CV_N * k] = tr;
}

static int cv_finite(const double *z, int m)
{
    for (int i = 0; i < m; ++i)
        if (!isfinite(z[i])) return 0;
    return 1;
}

/* RMS norm of z / (atol + rtol |z|) over the controlled components */
static double cv_norm(const double *v, const double *z, int m, double rtol, double atol)
{
    double s = 0.0;
    for (int i = 0; i < m; ++i) {
        double r = v[i] / (atol + rtol * fabs(z[i]));
        s += r * r;
    }
    return sqrt(s / m);
}

static double cv_initial_step(double t, const double *z, const double *f0, int k, const double *P,
                              double rtol, double atol, double span)
{
    const int m = CV_N + CV_N * k, mz = m + 1;
    double z1[CV_ZMAX], f1[CV_ZMAX];
    double d0 = cv_norm(z, z, m, rtol, atol), d1 = cv_norm(f0, z, m, rtol, atol);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    if (h0 > span) h0 = span;
    for (int i = 0; i < mz; ++i) z1[i] = z[i] + h0 * f0[i];
    cv_f(t + h0, z1, k, P, f1);
    for (int i = 0; i < mz; ++i) f1[i] -= f0[i];
    double d2 = cv_norm(f1, z, m, rtol, atol) / h0;
    double dm = d1 > d2 ? d1 : d2;
    double h1 = dm <= 1e-15 ? fmax(1e-6, h0 * 1e-3) : chaplygin_pow(0.01 / dm, 1.0 / 8.0);
    double h = fmin(100.0 * h0, h1);
    return h < span ? h : span;
}

int chaplygin_var_flow(double t0, double t1, double *z, int k, const double *P, double rtol,
                       double atol, long max_steps, double *stats)
{
    const int m = CV_N + CV_N * k, mz = m + 1;
    double K[CV_STAGES + 1][CV_ZMAX];
    double zs[CV_ZMAX], zn[CV_ZMAX], e3[CV_ZMAX], e5[CV_ZMAX];
    const double span = t1 - t0;
    if (span == 0.0) return 0;
    const double dir = span > 0 ? 1.0 : -1.0;
    double t = t0;
    cv_f(t, z, k, P, K[0]);
    stats[2] += 1;
    double h = fabs(stats[3]);
    if (!(h > 0.0) || !isfinite(h)) {
        h = cv_initial_step(t, z, K[0], k, P, rtol, atol, fabs(span));
        stats[2] += 1;
    }
    int rejected_last = 0;
    long steps = 0;
    while (dir * (t1 - t) > 0.0) {
        if (++steps > max_steps) return 1;
        const double hmin = 10.0 * DBL_EPSILON * fmax(fabs(t), fabs(t1));
        if (h < hmin) return 2;
        double hs = h;
        int last = 0;
        if (hs >= fabs(t1 - t)) {
            hs = fabs(t1 - t);
            last = 1;
        }
        const double hd = dir * hs;
        for (int s = 1; s < CV_STAGES; ++s) {
            for (int i = 0; i < mz; ++i) {
                double a = 0.0;
                for (int r = 0; r < s; ++r) a += DOP_A[s * CV_STAGES + r] * K[r][i];
                zs[i] = z[i] + hd * a;
            }
            cv_f(t + DOP_C[s] * hd, zs, k, P, K[s]);
        }
        for (int i = 0; i < mz; ++i) {
            double b = 0.0;
            for (int r = 0; r < CV_STAGES; ++r) b += DOP_B[r] * K[r][i];
            zn[i] = z[i] + hd * b;
        }
        const double tn = last ? t1 : t + hd;
        cv_f(tn, zn, k, P, K[CV_STAGES]);
        stats[2] += CV_STAGES;
        /* error estimate of dop853.f: err5 and err3 combined */
        double n5 = 0.0, n3 = 0.0;
        for (int i = 0; i < m; ++i) {
            double a5 = 0.0, a3 = 0.0;
            for (int r = 0; r <= CV_STAGES; ++r) {
                a5 += DOP_E5[r] * K[r][i];
                a3 += DOP_E3[r] * K[r][i];
            }
            const double sc = atol + rtol * fmax(fabs(z[i]), fabs(zn[i]));
            e5[i] = a5 / sc;
            e3[i] = a3 / sc;
            n5 += e5[i] * e5[i];
            n3 += e3[i] * e3[i];
        }
        double err = 0.0;
        if (n5 > 0.0 || n3 > 0.0) err = hs * n5 / sqrt((n5 + 0.01 * n3) * m);
        if (!isfinite(err)) {
            if (!cv_finite(zn, mz)) err = INFINITY;
        }
        if (err <= 1.0) {
            double fac = err == 0.0 ? 10.0 : 0.9 * chaplygin_pow(err, -1.0 / 8.0);
            if (fac > 10.0) fac = 10.0;
            if (rejected_last && fac > 1.0) fac = 1.0;
            if (fac < 0.2) fac = 0.2;
            t = tn;
            for (int i = 0; i < mz; ++i) {
                z[i] = zn[i];
                K[0][i] = K[CV_STAGES][i];
            }
            stats[0] += 1;
            if (!last || fac < 1.0) h = hs * fac;
            rejected_last = 0;
            if (!cv_finite(z, mz)) return 3;
        } else {
            double fac = isfinite(err) ? 0.9 * chaplygin_pow(err, -1.0 / 8.0) : 0.2;
            if (fac < 0.2) fac = 0.2;
            h = hs * fac;
            rejected_last = 1;
            stats[1] += 1;
        }
    }
    stats[3] = h;
    return 0;
}

void chaplygin_var_integral_gradients(double t, const double *y, const double *P, double *out)
{
    double e[CV_N], fp[CV_NI], fm[CV_NI];
    const int ni = CHAPLYGIN_N_INTEGRALS;
    for (int i = 0; i < CV_N; ++i) e[i] = y[i];
    for (int j = 0; j < CV_N; ++j) {
        const double h = chaplygin_cbrt(DBL_EPSILON) * fmax(1.0, fabs(y[j]));
        e[j] = y[j] + h;
        const double hp = e[j] - y[j];
        chaplygin_integrals(t, e, P, fp);
        e[j] = y[j] - h;
        const double hm = y[j] - e[j];
        chaplygin_integrals(t, e, P, fm);
        e[j] = y[j];
        for (int i = 0; i < ni; ++i) out[i * CV_N + j] = (fp[i] - fm[i]) / (hp + hm);
    }
}

/* orthonormal basis of the span of the integrals' gradients at (t, y); returns its size */
static int cv_normal_basis(double t, const double *y, const double *P, double *Q)
{
    const int ni = CHAPLYGIN_N_INTEGRALS;
    double G[CV_NI * CV_N];
    int r = 0;
    if (ni == 0) return 0;
    chaplygin_var_integral_gradients(t, y, P, G);
    for (int i = 0; i < ni; ++i) {
        double v[CV_N], n0 = 0.0, n1 = 0.0;
        for (int l = 0; l < CV_N; ++l) {
            v[l] = G[i * CV_N + l];
            n0 += v[l] * v[l];
        }
        for (int pass = 0; pass < 2; ++pass)
            for (int q = 0; q < r; ++q) {
                double d = 0.0;
                for (int l = 0; l < CV_N; ++l) d += Q[q * CV_N + l] * v[l];
                for (int l = 0; l < CV_N; ++l) v[l] -= d * Q[q * CV_N + l];
            }
        for (int l = 0; l < CV_N; ++l) n1 += v[l] * v[l];
        if (n0 == 0.0 || n1 <= 1e-16 * n0) continue; /* dependent (or vanishing) gradient */
        n1 = sqrt(n1);
        for (int l = 0; l < CV_N; ++l) Q[r * CV_N + l] = v[l] / n1;
        ++r;
    }
    return r;
}

int chaplygin_var_normal_rank(double t, const double *y, const double *P)
{
    double Q[CV_NI * CV_N];
    return cv_normal_basis(t, y, P, Q);
}

/* The end of an interval of one point (z its augmented state at tb): the divergence integral,
 * the projection onto the level set's tangent space and the QR of Benettin's loop (here and in
 * templates/variational_batch.c). Returns 0 or 3 (a vanishing or non-finite tangent vector).
 * project < 0: neither projection nor QR (the tangent vectors stay the flow's derivative
 * applied to the initial ones: the map Jacobians of flow_jacobians, one interval). */
static int cv_interval_end(double tb, double *z, int k, const double *P, int project,
                           double *logs, double *div)
{
    double *V = z + CV_N;
    double Q[CV_NI * CV_N];
    *div = z[CV_N + CV_N * k];
    if (project < 0) {
        for (int j = 0; j < k; ++j) logs[j] = 0.0;
        return 0;
    }
    if (project) {
        int r = cv_normal_basis(tb, z, P, Q);
        for (int j = 0; j < k; ++j)
            for (int q = 0; q < r; ++q) {
                double d = 0.0;
                for (int l = 0; l < CV_N; ++l) d += Q[q * CV_N + l] * V[l * k + j];
                for (int l = 0; l < CV_N; ++l) V[l * k + j] -= d * Q[q * CV_N + l];
            }
    }
    for (int j = 0; j < k; ++j) {
        double rjj = 0.0;
        for (int pass = 0; pass < 2; ++pass)
            for (int q = 0; q < j; ++q) {
                double d = 0.0;
                for (int l = 0; l < CV_N; ++l) d += V[l * k + q] * V[l * k + j];
                for (int l = 0; l < CV_N; ++l) V[l * k + j] -= d * V[l * k + q];
            }
        for (int l = 0; l < CV_N; ++l) rjj += V[l * k + j] * V[l * k + j];
        rjj = sqrt(rjj);
        if (!(rjj > 0.0) || !isfinite(rjj)) return 3;
        logs[j] = chaplygin_log(rjj);
        for (int l = 0; l < CV_N; ++l) V[l * k + j] /= rjj;
    }
    return 0;
}

int chaplygin_var_renormalised(double t0, double tau, long n_intervals, double *z, int k,
                               const double *P, double rtol, double atol, int project,
                               long max_steps, double *logs, double *divs, double *stats)
{
    const int iq = CV_N + CV_N * k;
    for (long it = 0; it < n_intervals; ++it) {
        const double ta = t0 + (double)it * tau, tb = t0 + (double)(it + 1) * tau;
        z[iq] = 0.0;
        int status = chaplygin_var_flow(ta, tb, z, k, P, rtol, atol, max_steps, stats);
        if (status) return status;
        status = cv_interval_end(tb, z, k, P, project, logs + it * k, divs + it);
        if (status) return status;
    }
    return 0;
}
