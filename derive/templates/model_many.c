/* chaplygin.numerics.compiled batch shim v2 */
#include <stddef.h>

typedef void (*chaplygin__routine)(double, const double *, const double *, double *);

static void chaplygin__many(chaplygin__routine fn, int m, double T, ptrdiff_t N,
                            const double *Y, ptrdiff_t YS0, ptrdiff_t YS1, const double *P,
                            double *OUT, ptrdiff_t OS0, ptrdiff_t OS1)
{
    int sizes[4];
    chaplygin_sizes(sizes);
    const int n = sizes[0];
    double y[n > 0 ? n : 1];
    double f[m > 0 ? m : 1];
    for (ptrdiff_t j = 0; j < N; ++j) {
        for (int i = 0; i < n; ++i) y[i] = Y[i * YS0 + j * YS1];
        fn(T, y, P, f);
        for (int k = 0; k < m; ++k) OUT[k * OS0 + j * OS1] = f[k];
    }
}

/* the same with a parameter set per state: P[i * PS0 + j * PS1] is parameter i of state j */
static void chaplygin__many_params(chaplygin__routine fn, int m, double T, ptrdiff_t N,
                                   const double *Y, ptrdiff_t YS0, ptrdiff_t YS1,
                                   const double *P, ptrdiff_t PS0, ptrdiff_t PS1, double *OUT,
                                   ptrdiff_t OS0, ptrdiff_t OS1)
{
    int sizes[4];
    chaplygin_sizes(sizes);
    const int n = sizes[0], np_ = sizes[1];
    double y[n > 0 ? n : 1];
    double p[np_ > 0 ? np_ : 1];
    double f[m > 0 ? m : 1];
    for (ptrdiff_t j = 0; j < N; ++j) {
        for (int i = 0; i < n; ++i) y[i] = Y[i * YS0 + j * YS1];
        for (int i = 0; i < np_; ++i) p[i] = P[i * PS0 + j * PS1];
        fn(T, y, p, f);
        for (int k = 0; k < m; ++k) OUT[k * OS0 + j * OS1] = f[k];
    }
}

#define CHAPLYGIN__MANY(NAME, M)                                                          \
    void chaplygin_many_##NAME(double T, ptrdiff_t N, const double *Y, ptrdiff_t YS0,    \
                               ptrdiff_t YS1, const double *P, double *OUT, ptrdiff_t OS0, \
                               ptrdiff_t OS1)                                             \
    {                                                                                     \
        int s[4];                                                                         \
        chaplygin_sizes(s);                                                               \
        chaplygin__many(chaplygin_##NAME, (M), T, N, Y, YS0, YS1, P, OUT, OS0, OS1);      \
    }                                                                                     \
    void chaplygin_many_params_##NAME(double T, ptrdiff_t N, const double *Y,            \
                                      ptrdiff_t YS0, ptrdiff_t YS1, const double *P,      \
                                      ptrdiff_t PS0, ptrdiff_t PS1, double *OUT,          \
                                      ptrdiff_t OS0, ptrdiff_t OS1)                       \
    {                                                                                     \
        int s[4];                                                                         \
        chaplygin_sizes(s);                                                               \
        chaplygin__many_params(chaplygin_##NAME, (M), T, N, Y, YS0, YS1, P, PS0, PS1, OUT, \
                               OS0, OS1);                                                 \
    }

CHAPLYGIN__MANY(rhs, s[0])
CHAPLYGIN__MANY(jac, s[0] * s[0])
CHAPLYGIN__MANY(aux, s[2])
CHAPLYGIN__MANY(integrals, s[3])
CHAPLYGIN__MANY(density, 1)
