/* detmath.h -- chaplygin's own double-precision transcendental functions: the same bits everywhere.
 *
 * Functions (static inline, C99, double precision), drop-in replacements of the libm functions of
 * the same names with the special values of C99 Annex F (pow, atan2, hypot included): chaplygin_exp,
 * _log, _log2, _log10, _pow, _sin, _cos, _atan, _atan2, _asin, _acos, _cbrt, _hypot, _sinh, _cosh.
 * errno is never set; every NaN result is the positive quiet NaN 0x7ff8000000000000 (the payload
 * of a NaN argument is not kept). chaplygin.arith.detmath performs the same operations on
 * Python floats and numpy arrays and gives the same bits.
 *
 * WHAT IS GUARANTEED
 * Accuracy: faithful rounding, error below 1 ulp for every argument (subnormal results included,
 * rounded once), and correctly rounded for more than 99.9% of arguments. Design: each function
 * forms its result as an unevaluated sum hi + lo -- argument reduction by exact steps or
 * double-double ones (Cody-Waite with pi/2 in four parts below 2^20, Payne-Hanek with 1216 bits of
 * 2/pi above; exact products by Dekker/Veltkamp splitting instead of FMA; tables of double-double
 * values), polynomials whose truncation errors are listed in the constants block -- whose relative
 * error before the one final rounding is below 2^-57 (below 2^-66 for atan, atan2, asin, acos,
 * cbrt, hypot): the error is at most 0.5 + 1/16 ulp, and the result is the correctly rounded one
 * unless the exact value lies that close to a midpoint. Measured against mpmath at 200 bits on
 * 10^5 arguments per function over every range that matters (tests/test_detmath.py): max error in
 * ulp (fraction correctly rounded) exp 0.5062 (99.958%), log 0.5004 (99.998%), log2 0.5002
 * (99.999%), log10 0.5015 (99.994%), pow 0.5047 (99.942%), sin 0.5049 (99.944%), cos 0.5051
 * (99.948%, arguments up to 1.8e308), atan 0.5000 (99.999%), atan2 0.5000 (100%), asin 0.5000
 * (100%), acos 0.5000 (100%), cbrt 0.5000 (100%), hypot 0.5000 (100%), sinh 0.5200 (99.910%),
 * cosh 0.5049 (99.926%). sin and cos are right for every finite argument.
 *
 * The same bits on every machine: only IEEE-754 basic operations in double precision (+ - * / and
 * sqrt, each correctly rounded to nearest), comparisons, exact conversions between doubles and
 * integers, exact scaling by powers of two, integer and bit operations (memcpy bit casts, shifts,
 * 64-bit integer products). fabs and sqrt are the only <math.h> functions called (both exact); no
 * libm code path (glibc picks FMA/AVX2 variants of exp, log, sin, ... by processor) and no
 * CPU-dependent dispatch. C does not let the compiler reassociate floating-point operations, so
 * the source fixes every rounding, provided that
 *  (1) there is no FMA contraction: compile with -ffp-contract=off (chaplygin.numerics.ccompile's
 *      CFLAGS do). The #pragma STDC FP_CONTRACT OFF below also covers clang's default
 *      (-ffp-contract=on); gcc's GNU modes (-std=gnu*) default to -ffp-contract=fast, which on a
 *      target with FMA (every AArch64; x86-64 with -mfma or -march=native) fuses a*b + c and
 *      changes the bits -- a contracted Dekker product no longer yields the exact error (measured
 *      with -march=native -ffp-contract=fast on 80000 arguments: other bits for 14 of the 15
 *      functions with gcc, up to 10% of the arguments for hypot, and for 6 with clang);
 *  (2) double arithmetic is evaluated in double precision (FLT_EVAL_METHOD == 0: SSE2 on x86-64,
 *      every AArch64); x87 extended precision (32-bit x86) is refused below;
 *  (3) no -ffast-math (refused below) and the default rounding mode, round to nearest.
 * The Payne-Hanek reduction multiplies 64-bit integers with unsigned __int128 (gcc and clang on
 * 64-bit targets, x86-64 and AArch64) or, without it or with CHAPLYGIN_DETMATH_NO_INT128 defined,
 * with 32-bit halves; integer products are exact, so both paths give the same bits.
 * Tested here (x86-64, tests/test_detmath.py): gcc 12 and clang 14 at -O0 and -O2 (by hand also
 * -O3 -march=native), both Payne-Hanek paths and the Python/numpy port give identical bits on 1.5
 * million arguments. AArch64: the same source gives the same bits by (1)-(3) (IEEE double,
 * correctly rounded sqrt, __int128 available); it has FMA instructions, so -ffp-contract=off is
 * essential: clang 14 targeting aarch64 with the project's flags emits no fused multiply-add
 * (checked on the assembly, 193 with -ffp-contract=fast); not run on ARM hardware here.
 *
 * Speed, ns per call, detmath / glibc 2.36 (examples/bench/detmath_speed.py: best of 200 loops of
 * 10^4 random arguments, shared x86-64 machine with FMA): exp 5.5 / 6.1, log 7.0 / 4.3, log2
 * 8.6 / 4.0, log10 8.7 / 8.4, pow 28 / 14, sin 28 / 19 (|x| ~ 1e100: 36 / 72), cos 26 / 18, atan
 * 18-22 / 10, atan2 33 / 23, asin 35 / 13-16, acos 36 / 14-16, cbrt 20 / 16, hypot 20 / 17,
 * sinh 15 / 20, cosh 12 / 7. Within 2x of glibc except log2, pow and atan (about 2.1x) and asin,
 * acos (2.3-2.6x): the exact products and double-double steps that replace FMA cost most where
 * glibc's FMA code is shortest.
 *
 * The algorithms are this project's own (range reduction + Taylor polynomials, no code taken from
 * fdlibm, musl or glibc); every constant is computed with mpmath by arith/detmath_tables.py.
 */
#ifndef CHAPLYGIN_DETMATH_H
#define CHAPLYGIN_DETMATH_H

#include <float.h>
#include <math.h> /* only the exact operations fabs and sqrt */
#include <stdint.h>
#include <string.h> /* memcpy for bit casts */

#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "detmath.h needs FLT_EVAL_METHOD == 0 (double operations rounded to double: SSE2, ARM; not x87)"
#endif
#if defined(__FAST_MATH__)
#error "detmath.h must not be compiled with -ffast-math (it relies on IEEE-754 operation order)"
#endif
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

/* ---- BEGIN GENERATED CONSTANTS (chaplygin.derive.emit.detmath_header) ---- */
/* Do not edit: regenerate with
 * `python -m chaplygin.derive.emit.detmath_header --write`.
 * Cody-Waite |pi/2 - (P1+P2+P3+P4)| = 2^-159.9
 * exp: |r| <= 0.00270761; Taylor degree 6, relative truncation < 2^-72.0
 * log: |u| <= 2^-8.349
 * log: Taylor to u^7, truncation < 2^-61.4 |u|
 * log (double-double, for pow): Taylor to u^8, truncation < 2^-70.0 |u|
 * sin |r| < 1/8: Taylor to r^11, truncation < 2^-68.5 |r|; cos: to r^10, truncation < 2^-64.8
 * sin/cos table path: |d| <= 1/256, sin d to d^5 (truncation < 2^-68.3), cos d to d^6 (truncation < 2^-79.3)
 * atan: |t| <= 1/128, Taylor to t^9, truncation < 2^-73.5 |t|
 * sinh |x| < 1/4: Taylor to x^13, truncation < 2^-68.2 |x|
 * cbrt: starting guess relative error < 2^-19.1
 */
static const double chaplygin_dm_LN2_HI = 0x1.62e42fefa3800p-1;
static const double chaplygin_dm_LN2_LO = 0x1.ef35793c76730p-45;
static const double chaplygin_dm_PIO2_HI = 0x1.921fb54442d18p+0;
static const double chaplygin_dm_PIO2_LO = 0x1.1a62633145c07p-54;
static const double chaplygin_dm_PI_HI = 0x1.921fb54442d18p+1;
static const double chaplygin_dm_PI_LO = 0x1.1a62633145c07p-53;
static const double chaplygin_dm_PI3O4 = 0x1.2d97c7f3321d2p+1;
static const double chaplygin_dm_PI_O4 = 0x1.921fb54442d18p-1;
static const double chaplygin_dm_INV_PIO2 = 0x1.45f306dc9c883p-1;
static const double chaplygin_dm_CW_P1 = 0x1.921fb54400000p+0;
static const double chaplygin_dm_CW_P2 = 0x1.0b4611a600000p-34;
static const double chaplygin_dm_CW_P3 = 0x1.3198a2e000000p-69;
static const double chaplygin_dm_CW_P4 = 0x1.b839a252049c1p-104;
static const double chaplygin_dm_EXP_INV_LN2_N = 0x1.71547652b82fep+7;
static const double chaplygin_dm_EXP_LN2_N_HI = 0x1.62e42fefc0000p-8;
static const double chaplygin_dm_EXP_LN2_N_LO = -0x1.c610ca86c3899p-44;
static const double chaplygin_dm_EXP_POLY[5] = {
    0x1.0000000000000p-1, 0x1.5555555555555p-3, 0x1.5555555555555p-5,
    0x1.1111111111111p-7, 0x1.6c16c16c16c17p-10,
};
static const double chaplygin_dm_EXP_T_HI[128] = {
    0x1.0000000000000p+0, 0x1.0163da9fb3335p+0, 0x1.02c9a3e778061p+0,
    0x1.04315e86e7f85p+0, 0x1.059b0d3158574p+0, 0x1.0706b29ddf6dep+0,
    0x1.0874518759bc8p+0, 0x1.09e3ecac6f383p+0, 0x1.0b5586cf9890fp+0,
    0x1.0cc922b7247f7p+0, 0x1.0e3ec32d3d1a2p+0, 0x1.0fb66affed31bp+0,
    0x1.11301d0125b51p+0, 0x1.12abdc06c31ccp+0, 0x1.1429aaea92de0p+0,
    0x1.15a98c8a58e51p+0, 0x1.172b83c7d517bp+0, 0x1.18af9388c8deap+0,
    0x1.1a35beb6fcb75p+0, 0x1.1bbe084045cd4p+0, 0x1.1d4873168b9aap+0,
    0x1.1ed5022fcd91dp+0, 0x1.2063b88628cd6p+0, 0x1.21f49917ddc96p+0,
    0x1.2387a6e756238p+0, 0x1.251ce4fb2a63fp+0, 0x1.26b4565e27cddp+0,
    0x1.284dfe1f56381p+0, 0x1.29e9df51fdee1p+0, 0x1.2b87fd0dad990p+0,
    0x1.2d285a6e4030bp+0, 0x1.2ecafa93e2f56p+0, 0x1.306fe0a31b715p+0,
    0x1.32170fc4cd831p+0, 0x1.33c08b26416ffp+0, 0x1.356c55f929ff1p+0,
    0x1.371a7373aa9cbp+0, 0x1.38cae6d05d866p+0, 0x1.3a7db34e59ff7p+0,
    0x1.3c32dc313a8e5p+0, 0x1.3dea64c123422p+0, 0x1.3fa4504ac801cp+0,
    0x1.4160a21f72e2ap+0, 0x1.431f5d950a897p+0, 0x1.44e086061892dp+0,
    0x1.46a41ed1d0057p+0, 0x1.486a2b5c13cd0p+0, 0x1.4a32af0d7d3dep+0,
    0x1.4bfdad5362a27p+0, 0x1.4dcb299fddd0dp+0, 0x1.4f9b2769d2ca7p+0,
    0x1.516daa2cf6642p+0, 0x1.5342b569d4f82p+0, 0x1.551a4ca5d920fp+0,
    0x1.56f4736b527dap+0, 0x1.58d12d497c7fdp+0, 0x1.5ab07dd485429p+0,
    0x1.5c9268a5946b7p+0, 0x1.5e76f15ad2148p+0, 0x1.605e1b976dc09p+0,
    0x1.6247eb03a5585p+0, 0x1.6434634ccc320p+0, 0x1.6623882552225p+0,
    0x1.68155d44ca973p+0, 0x1.6a09e667f3bcdp+0, 0x1.6c012750bdabfp+0,
    0x1.6dfb23c651a2fp+0, 0x1.6ff7df9519484p+0, 0x1.71f75e8ec5f74p+0,
    0x1.73f9a48a58174p+0, 0x1.75feb564267c9p+0, 0x1.780694fde5d3fp+0,
    0x1.7a11473eb0187p+0, 0x1.7c1ed0130c132p+0, 0x1.7e2f336cf4e62p+0,
    0x1.80427543e1a12p+0, 0x1.82589994cce13p+0, 0x1.8471a4623c7adp+0,
    0x1.868d99b4492edp+0, 0x1.88ac7d98a6699p+0, 0x1.8ace5422aa0dbp+0,
    0x1.8cf3216b5448cp+0, 0x1.8f1ae99157736p+0, 0x1.9145b0b91ffc6p+0,
    0x1.93737b0cdc5e5p+0, 0x1.95a44cbc8520fp+0, 0x1.97d829fde4e50p+0,
    0x1.9a0f170ca07bap+0, 0x1.9c49182a3f090p+0, 0x1.9e86319e32323p+0,
    0x1.a0c667b5de565p+0, 0x1.a309bec4a2d33p+0, 0x1.a5503b23e255dp+0,
    0x1.a799e1330b358p+0, 0x1.a9e6b5579fdbfp+0, 0x1.ac36bbfd3f37ap+0,
    0x1.ae89f995ad3adp+0, 0x1.b0e07298db666p+0, 0x1.b33a2b84f15fbp+0,
    0x1.b59728de5593ap+0, 0x1.b7f76f2fb5e47p+0, 0x1.ba5b030a1064ap+0,
    0x1.bcc1e904bc1d2p+0, 0x1.bf2c25bd71e09p+0, 0x1.c199bdd85529cp+0,
    0x1.c40ab5fffd07ap+0, 0x1.c67f12e57d14bp+0, 0x1.c8f6d9406e7b5p+0,
    0x1.cb720dcef9069p+0, 0x1.cdf0b555dc3fap+0, 0x1.d072d4a07897cp+0,
    0x1.d2f87080d89f2p+0, 0x1.d5818dcfba487p+0, 0x1.d80e316c98398p+0,
    0x1.da9e603db3285p+0, 0x1.dd321f301b460p+0, 0x1.dfc97337b9b5fp+0,
    0x1.e264614f5a129p+0, 0x1.e502ee78b3ff6p+0, 0x1.e7a51fbc74c83p+0,
    0x1.ea4afa2a490dap+0, 0x1.ecf482d8e67f1p+0, 0x1.efa1bee615a27p+0,
    0x1.f252b376bba97p+0, 0x1.f50765b6e4540p+0, 0x1.f7bfdad9cbe14p+0,
    0x1.fa7c1819e90d8p+0, 0x1.fd3c22b8f71f1p+0,
};
static const double chaplygin_dm_EXP_T_LO[128] = {
    0x0.0p+0, 0x1.b61299ab8cdb7p-54, -0x1.19083535b085dp-56,
    -0x1.0a31c1977c96ep-54, 0x1.d73e2a475b465p-55, -0x1.c91dfe2b13c27p-55,
    0x1.186be4bb284ffp-57, 0x1.1487818316136p-54, 0x1.8a62e4adc610bp-54,
    0x1.01edc16e24f71p-54, 0x1.03a1727c57b53p-59, -0x1.b9bedc44ebd7bp-57,
    -0x1.6c51039449b3ap-54, -0x1.1b514b36ca5c7p-58, -0x1.32fbf9af1369ep-54,
    0x1.2406ab9eeab0ap-55, -0x1.19041b9d78a76p-55, -0x1.11023d1970f6cp-54,
    0x1.e5b4c7b4968e4p-55, -0x1.95386352ef607p-54, 0x1.e016e00a2643cp-54,
    -0x1.1df98027bb78cp-54, 0x1.dc775814a8495p-55, 0x1.2a97e9494a5eep-55,
    0x1.9b07eb6c70573p-54, 0x1.ac155bef4f4a4p-55, 0x1.2bd339940e9d9p-55,
    -0x1.a4c3a8c3f0d7ep-54, 0x1.612e8afad1255p-55, -0x1.10adcd6381aa4p-59,
    0x1.0024754db41d5p-54, 0x1.1ca0f45d52383p-56, 0x1.6f46ad23182e4p-55,
    0x1.a9ce78e18047cp-55, 0x1.32721843659a6p-54, -0x1.b5cee5c4e4628p-55,
    -0x1.63aeabf42eae2p-54, -0x1.e958d3c9904bdp-54, -0x1.5e436d661f5e3p-56,
    -0x1.efff8375d29c3p-54, 0x1.ada0911f09ebcp-55, -0x1.7d023f956f9f3p-54,
    -0x1.ef3691c309278p-58, -0x1.1c7dde35f7999p-55, 0x1.89b7a04ef80d0p-59,
    0x1.c944bd1648a76p-54, 0x1.3c1a3b69062f0p-56, 0x1.9cb62f3d1be56p-54,
    0x1.d4397afec42e2p-56, 0x1.8ecdbbc6a7833p-54, -0x1.4b309d25957e3p-54,
    -0x1.f768569bd93efp-55, -0x1.07abe1db13cadp-55, -0x1.d689cefede59bp-55,
    0x1.9bb2c011d93adp-54, 0x1.295e15b9a1de8p-55, 0x1.6324c054647adp-54,
    0x1.c4b1b816986a2p-60, 0x1.ba6f93080e65ep-54, -0x1.3e2429b56de47p-54,
    -0x1.383c17e40b497p-54, -0x1.c483c759d8933p-55, -0x1.bb60987591c34p-54,
    0x1.038ae44f73e65p-57, -0x1.bdd3413b26456p-54, -0x1.2895667ff0b0dp-56,
    -0x1.bbe3a683c88abp-57, -0x1.83c0f25860ef6p-55, -0x1.16e4786887a99p-55,
    -0x1.0a8d96c65d53cp-54, -0x1.0245957316dd3p-54, 0x1.866b80a02162dp-54,
    -0x1.41577ee04992fp-55, 0x1.f124cd1164dd6p-54, 0x1.05d02ba15797ep-56,
    -0x1.27c86626d972bp-54, -0x1.d4c1dd41532d8p-54, -0x1.8d684a341cdfbp-55,
    -0x1.fc6f89bd4f6bap-54, 0x1.994c2f37cb53ap-54, 0x1.6e9f156864b27p-54,
    -0x1.0d55e32e9e3aap-56, 0x1.5cc13a2e3976cp-55, -0x1.dd6792e582524p-54,
    -0x1.75fc781b57ebcp-57, -0x1.64b7c96a5f039p-56, -0x1.d185b7c1b85d1p-54,
    -0x1.173bd91cee632p-54, 0x1.c7c46b071f2bep-56, 0x1.824ca78e64c6ep-56,
    -0x1.359495d1cd533p-54, 0x1.6305c7ddc36abp-54, -0x1.d2f6edb8d41e1p-54,
    0x1.bcb7ecac563c7p-54, 0x1.0fac90ef7fd31p-54, -0x1.f9234cae76cd0p-55,
    0x1.7a1cd345dcc81p-54, -0x1.bdef54c80e425p-54, -0x1.2805e3084d708p-57,
    -0x1.c71dfbbba6de3p-54, -0x1.5584f7e54ac3bp-56, -0x1.efcd30e54292ep-54,
    0x1.23dd07a2d9e84p-55, -0x1.efdca3f6b9c73p-54, 0x1.11065895048ddp-55,
    0x1.b4537e083c60ap-54, 0x1.2884dff483cadp-54, 0x1.1acbc48805c44p-56,
    0x1.503cbd1e949dbp-56, -0x1.dd83b53829d72p-55, -0x1.cbc3743797a9cp-54,
    -0x1.d487b719d8578p-54, 0x1.2ed02d75b3707p-55, -0x1.11ec18beddfe8p-54,
    0x1.c2300696db532p-54, 0x1.2da5778f018c3p-54, -0x1.1a5cd4f184b5cp-54,
    -0x1.7b627817a1496p-54, 0x1.39e8980a9cc8fp-55, 0x1.2d522ca0c8de2p-54,
    -0x1.e9c23179c2893p-54, -0x1.c93f3b411ad8cp-54, 0x1.dc7f486a4b6b0p-54,
    0x1.3a1a5bf0d8e43p-54, 0x1.9d3e12dd8a18bp-54, -0x1.dbb12d006350ap-54,
    0x1.74853f3a5931ep-55, 0x1.2eb74966579e7p-57,
};
static const double chaplygin_dm_LOG_SQRT2 = 0x1.6a09e667f3bcdp+0;
static const double chaplygin_dm_LOG_R[182] = {
    0x1.6a00000000000p+0, 0x1.6800000000000p+0, 0x1.6600000000000p+0,
    0x1.6440000000000p+0, 0x1.6240000000000p+0, 0x1.6040000000000p+0,
    0x1.5e80000000000p+0, 0x1.5c80000000000p+0, 0x1.5ac0000000000p+0,
    0x1.5900000000000p+0, 0x1.5700000000000p+0, 0x1.5540000000000p+0,
    0x1.5380000000000p+0, 0x1.51c0000000000p+0, 0x1.5000000000000p+0,
    0x1.4e40000000000p+0, 0x1.4cc0000000000p+0, 0x1.4b00000000000p+0,
    0x1.4940000000000p+0, 0x1.47c0000000000p+0, 0x1.4600000000000p+0,
    0x1.4480000000000p+0, 0x1.42c0000000000p+0, 0x1.4140000000000p+0,
    0x1.3fc0000000000p+0, 0x1.3e40000000000p+0, 0x1.3c80000000000p+0,
    0x1.3b00000000000p+0, 0x1.3980000000000p+0, 0x1.3800000000000p+0,
    0x1.3680000000000p+0, 0x1.3540000000000p+0, 0x1.33c0000000000p+0,
    0x1.3240000000000p+0, 0x1.30c0000000000p+0, 0x1.2f80000000000p+0,
    0x1.2e00000000000p+0, 0x1.2c80000000000p+0, 0x1.2b40000000000p+0,
    0x1.2a00000000000p+0, 0x1.2880000000000p+0, 0x1.2740000000000p+0,
    0x1.2600000000000p+0, 0x1.2480000000000p+0, 0x1.2340000000000p+0,
    0x1.2200000000000p+0, 0x1.20c0000000000p+0, 0x1.1f80000000000p+0,
    0x1.1e40000000000p+0, 0x1.1d00000000000p+0, 0x1.1bc0000000000p+0,
    0x1.1a80000000000p+0, 0x1.1940000000000p+0, 0x1.1800000000000p+0,
    0x1.1700000000000p+0, 0x1.15c0000000000p+0, 0x1.1480000000000p+0,
    0x1.1340000000000p+0, 0x1.1240000000000p+0, 0x1.1100000000000p+0,
    0x1.1000000000000p+0, 0x1.0ec0000000000p+0, 0x1.0dc0000000000p+0,
    0x1.0c80000000000p+0, 0x1.0b80000000000p+0, 0x1.0a80000000000p+0,
    0x1.0940000000000p+0, 0x1.0840000000000p+0, 0x1.0740000000000p+0,
    0x1.0640000000000p+0, 0x1.0500000000000p+0, 0x1.0400000000000p+0,
    0x1.0300000000000p+0, 0x1.0200000000000p+0, 0x1.0100000000000p+0,
    0x1.0000000000000p+0, 0x1.fe00000000000p-1, 0x1.fc00000000000p-1,
    0x1.fa00000000000p-1, 0x1.f800000000000p-1, 0x1.f600000000000p-1,
    0x1.f480000000000p-1, 0x1.f280000000000p-1, 0x1.f080000000000p-1,
    0x1.ee80000000000p-1, 0x1.ed00000000000p-1, 0x1.eb00000000000p-1,
    0x1.e900000000000p-1, 0x1.e780000000000p-1, 0x1.e580000000000p-1,
    0x1.e380000000000p-1, 0x1.e200000000000p-1, 0x1.e000000000000p-1,
    0x1.de80000000000p-1, 0x1.dc80000000000p-1, 0x1.db00000000000p-1,
    0x1.d900000000000p-1, 0x1.d780000000000p-1, 0x1.d600000000000p-1,
    0x1.d400000000000p-1, 0x1.d280000000000p-1, 0x1.d100000000000p-1,
    0x1.cf00000000000p-1, 0x1.cd80000000000p-1, 0x1.cc00000000000p-1,
    0x1.ca80000000000p-1, 0x1.c880000000000p-1, 0x1.c700000000000p-1,
    0x1.c580000000000p-1, 0x1.c400000000000p-1, 0x1.c280000000000p-1,
    0x1.c100000000000p-1, 0x1.bf80000000000p-1, 0x1.be00000000000p-1,
    0x1.bc80000000000p-1, 0x1.bb00000000000p-1, 0x1.b980000000000p-1,
    0x1.b800000000000p-1, 0x1.b680000000000p-1, 0x1.b500000000000p-1,
    0x1.b380000000000p-1, 0x1.b200000000000p-1, 0x1.b080000000000p-1,
    0x1.af00000000000p-1, 0x1.ad80000000000p-1, 0x1.ac80000000000p-1,
    0x1.ab00000000000p-1, 0x1.a980000000000p-1, 0x1.a800000000000p-1,
    0x1.a700000000000p-1, 0x1.a580000000000p-1, 0x1.a400000000000p-1,
    0x1.a300000000000p-1, 0x1.a180000000000p-1, 0x1.a000000000000p-1,
    0x1.9f00000000000p-1, 0x1.9d80000000000p-1, 0x1.9c00000000000p-1,
    0x1.9b00000000000p-1, 0x1.9980000000000p-1, 0x1.9880000000000p-1,
    0x1.9700000000000p-1, 0x1.9600000000000p-1, 0x1.9480000000000p-1,
    0x1.9380000000000p-1, 0x1.9200000000000p-1, 0x1.9100000000000p-1,
    0x1.8f80000000000p-1, 0x1.8e80000000000p-1, 0x1.8d00000000000p-1,
    0x1.8c00000000000p-1, 0x1.8b00000000000p-1, 0x1.8980000000000p-1,
    0x1.8880000000000p-1, 0x1.8780000000000p-1, 0x1.8600000000000p-1,
    0x1.8500000000000p-1, 0x1.8400000000000p-1, 0x1.8280000000000p-1,
    0x1.8180000000000p-1, 0x1.8080000000000p-1, 0x1.7f80000000000p-1,
    0x1.7e00000000000p-1, 0x1.7d00000000000p-1, 0x1.7c00000000000p-1,
    0x1.7b00000000000p-1, 0x1.7980000000000p-1, 0x1.7880000000000p-1,
    0x1.7780000000000p-1, 0x1.7680000000000p-1, 0x1.7580000000000p-1,
    0x1.7480000000000p-1, 0x1.7380000000000p-1, 0x1.7280000000000p-1,
    0x1.7100000000000p-1, 0x1.7000000000000p-1, 0x1.6f00000000000p-1,
    0x1.6e00000000000p-1, 0x1.6d00000000000p-1, 0x1.6c00000000000p-1,
    0x1.6b00000000000p-1, 0x1.6a00000000000p-1,
};
static const double chaplygin_dm_LOG_L_HI[182] = {
    -0x1.62c82f2b9c000p-2, -0x1.5d1bdbf581000p-2, -0x1.5767717456000p-2,
    -0x1.5262deeb99000p-2, -0x1.4c9f09e153000p-2, -0x1.46d2d9c280000p-2,
    -0x1.41b941cce1000p-2, -0x1.3bdd24eb15000p-2, -0x1.36b5776bc1000p-2,
    -0x1.31871c9544000p-2, -0x1.2b9303ab8a000p-2, -0x1.26561f1338000p-2,
    -0x1.2112559861000p-2, -0x1.1bc794fd1d000p-2, -0x1.1675cababa000p-2,
    -0x1.111ce4003f000p-2, -0x1.0c81d4860b000p-2, -0x1.071b85fcd6000p-2,
    -0x1.01ade3913a000p-2, -0x1.fa01c3bb58000p-3, -0x1.ef0adcbdc6000p-3,
    -0x1.e598ed5a88000p-3, -0x1.da85d620ce000p-3, -0x1.d0fb7f2256000p-3,
    -0x1.c765b9e4d6000p-3, -0x1.bdc46ae344000p-3, -0x1.b2797ee464000p-3,
    -0x1.a8becfc882000p-3, -0x1.9ef83d276a000p-3, -0x1.9525a9cf46000p-3,
    -0x1.8b46f82236000p-3, -0x1.83040c91bc000p-3, -0x1.790ed4ee26000p-3,
    -0x1.6f0d28ae56000p-3, -0x1.64fee88260000p-3, -0x1.5c94007598000p-3,
    -0x1.526e5e3a1c000p-3, -0x1.483bccce6e000p-3, -0x1.3fb25a5952000p-3,
    -0x1.371fc201e8000p-3, -0x1.2cca0f5f60000p-3, -0x1.2423113ba6000p-3,
    -0x1.1b72ad52f6000p-3, -0x1.10f8e42254000p-3, -0x1.08338affa2000p-3,
    -0x1.fec9131dc0000p-4, -0x1.ed1794e838000p-4, -0x1.db5270187c000p-4,
    -0x1.c97978d790000p-4, -0x1.b78c82bb10000p-4, -0x1.a58b60c2b4000p-4,
    -0x1.9375e55594000p-4, -0x1.814be23f8c000p-4, -0x1.6f0d28ae58000p-4,
    -0x1.60658a9374000p-4, -0x1.4e01108a34000p-4, -0x1.3b87598b1c000p-4,
    -0x1.28f83450ec000p-4, -0x1.1a0fba1bf8000p-4, -0x1.0759835990000p-4,
    -0x1.f0a30c0118000p-5, -0x1.cae72fb960000p-5, -0x1.ac97221710000p-5,
    -0x1.868a830840000p-5, -0x1.67f94f0948000p-5, -0x1.494acc34d8000p-5,
    -0x1.22c71bcea8000p-5, -0x1.03d5d85e70000p-5, -0x1.c98d18d010000p-6,
    -0x1.8b31facaa0000p-6, -0x1.3cea443470000p-6, -0x1.fc0a8b0fc0000p-7,
    -0x1.7dc475f820000p-7, -0x1.fe02a6b100000p-8, -0x1.ff00aa2b00000p-9,
    0x0.0p+0, 0x1.0080559580000p-8, 0x1.0101575880000p-7,
    0x1.82448a3880000p-7, 0x1.0205658930000p-6, 0x1.432a925980000p-6,
    0x1.74321d3d00000p-6, 0x1.b5cc258b70000p-6, 0x1.f7a9b16780000p-6,
    0x1.1ce5a62bc0000p-5, 0x1.35c8bfaa10000p-5, 0x1.5715c4c040000p-5,
    0x1.788595a358000p-5, 0x1.91b073efd8000p-5, 0x1.b35dd9b588000p-5,
    0x1.d52ed64060000p-5, 0x1.eea31c0068000p-5, 0x1.08598b59e4000p-4,
    0x1.152b799bb4000p-4, 0x1.26536c3d8c000p-4, 0x1.333d7f8184000p-4,
    0x1.4485e03dbc000p-4, 0x1.5188742260000p-4, 0x1.5e95a4d978000p-4,
    0x1.700d30aeac000p-4, 0x1.7d33687c28000p-4, 0x1.8a6477a91c000p-4,
    0x1.9c0c32d4d4000p-4, 0x1.a956d3ecac000p-4, 0x1.b6ac88dad4000p-4,
    0x1.c40d6425a4000p-4, 0x1.d5f5565920000p-4, 0x1.e3707ee304000p-4,
    0x1.f0f70cdd98000p-4, 0x1.fe89139dbc000p-4, 0x1.06135354d4000p-3,
    0x1.0ce7ecdccc000p-3, 0x1.13c2605c3a000p-3, 0x1.1aa2b7e240000p-3,
    0x1.2188fd9808000p-3, 0x1.28753bc11a000p-3, 0x1.2f677cbbc0000p-3,
    0x1.365fcb015a000p-3, 0x1.3d5e3126bc000p-3, 0x1.4462b9dc9c000p-3,
    0x1.4b6d6fefe2000p-3, 0x1.527e5e4a1c000p-3, 0x1.59958ff1d6000p-3,
    0x1.60b3100b0a000p-3, 0x1.67d6e9d786000p-3, 0x1.6c9d07d204000p-3,
    0x1.73cb9074fe000p-3, 0x1.7b00916516000p-3, 0x1.823c16551a000p-3,
    0x1.871213750e000p-3, 0x1.8e588ebac2000p-3, 0x1.95a5adcf70000p-3,
    0x1.9a8778deba000p-3, 0x1.a1dfc40f1c000p-3, 0x1.a93ed3c8ae000p-3,
    0x1.ae2ca6f672000p-3, 0x1.b5971a213a000p-3, 0x1.bd087383be000p-3,
    0x1.c2028ab180000p-3, 0x1.c97f8079d4000p-3, 0x1.ce816157f2000p-3,
    0x1.d60a17f904000p-3, 0x1.db13db0d48000p-3, 0x1.e2a877a6b2000p-3,
    0x1.e7ba35eb78000p-3, 0x1.ef5ade4dd0000p-3, 0x1.f474b134e0000p-3,
    0x1.fc218be620000p-3, 0x1.00a1c6adda000p-2, 0x1.047e60cde8000p-2,
    0x1.07138604d6000p-2, 0x1.09aa572e6c000p-2, 0x1.0d8fb813eb000p-2,
    0x1.102ac0a35d000p-2, 0x1.12c77cd007000p-2, 0x1.16b5ccbad0000p-2,
    0x1.1956d3b9bc000p-2, 0x1.1bf99635a7000p-2, 0x1.1ff0fe7cf4000p-2,
    0x1.22981fbef8000p-2, 0x1.25410494e5000p-2, 0x1.27ebaf58d9000p-2,
    0x1.2bef07cdc9000p-2, 0x1.2e9e2bce12000p-2, 0x1.314f1e1d36000p-2,
    0x1.3401e12aed000p-2, 0x1.3811728565000p-2, 0x1.3ac8ca38e6000p-2,
    0x1.3d81fb5947000p-2, 0x1.403d086cea000p-2, 0x1.42f9f3ff62000p-2,
    0x1.45b8c0a17e000p-2, 0x1.487970e958000p-2, 0x1.4b3c077268000p-2,
    0x1.4f637ebbaa000p-2, 0x1.522ae0738a000p-2, 0x1.54f431b7be000p-2,
    0x1.57bf753c8d000p-2, 0x1.5a8cadbbee000p-2, 0x1.5d5bddf596000p-2,
    0x1.602d08af09000p-2, 0x1.630030b3ab000p-2,
};
static const double chaplygin_dm_LOG_L_LO[182] = {
    -0x1.e54bdbd7c8a98p-44, 0x1.8d6bdc9c7c238p-44, 0x1.64ead9524d7cap-44,
    0x1.e1b9f70894a01p-44, 0x1.e1dde70e02de0p-45, -0x1.59b275f67f75ap-44,
    0x1.0469013e43fc9p-44, 0x1.257b4970e6ed9p-44, -0x1.169785a9c223fp-46,
    -0x1.84fab94cecfd9p-46, 0x1.6db12d6bfb0a5p-45, -0x1.8b48866faa45fp-44,
    -0x1.82e78ba2950c4p-44, 0x1.ccf0c747ba7bep-44, -0x1.8380e731f55c4p-44,
    0x1.b3237096b4b6bp-46, 0x1.e5bcf401d1731p-44, 0x1.bcb8ba3e01a11p-44,
    0x1.08930ccdc1521p-46, 0x1.a1f71fae1d786p-46, 0x1.b26b79c86af24p-45,
    0x1.d134bcf1e98a1p-47, -0x1.40194c16cc7ecp-45, 0x1.af52b20633b29p-47,
    -0x1.1ab6b36976f6cp-44, -0x1.625b4023d6505p-44, 0x1.be88a906d00a9p-44,
    -0x1.e3185cf21b9cfp-44, 0x1.730b7b3f9ce00p-45, 0x1.297137d9f158fp-44,
    -0x1.2d9f2102dd7c9p-46, -0x1.e5b71c6e66f32p-44, -0x1.99bbd4e7746f6p-46,
    -0x1.69737c93373dap-44, 0x1.da40d759dded6p-46, 0x1.a8d948cd23322p-44,
    0x1.790ba37fc5238p-44, -0x1.eea52723f6369p-46, -0x1.195be6b358ff7p-44,
    -0x1.ee8779b2d8abcp-44, 0x1.b5ef191aff120p-44, 0x1.e3a0078ee9d9cp-44,
    -0x1.e80a41811a396p-45, 0x1.93b3843396307p-45, -0x1.0533cac823e27p-44,
    0x1.54555d1ae6607p-44, 0x1.fd143749d0484p-46, -0x1.9277856ae181fp-44,
    0x1.6e010977d1884p-44, 0x1.25ef7bc3987e7p-44, 0x1.cdc735c5c9f2ap-44,
    -0x1.eddc37380c364p-44, -0x1.b2381da82fdfdp-51, 0x1.4b4641b664613p-44,
    -0x1.0c3b1dee9c4f8p-44, -0x1.ae5cfdf2c5ae5p-44, 0x1.2241594aca313p-45,
    -0x1.a8d75aa119769p-44, -0x1.4a3fcc319d6dcp-45, 0x1.b8ecfe4b59987p-44,
    0x1.d599e83368e91p-45, 0x1.efabf2025b1bep-44, -0x1.f8d3ef013222cp-45,
    0x1.2623a134ac693p-46, -0x1.ecc1f3e7e4ed7p-44, -0x1.11c78a56fd247p-45,
    -0x1.d2818f87f888fp-48, -0x1.f778960ed29cfp-44, 0x1.bf6150589df0fp-45,
    0x1.3fc78a96e4964p-44, 0x1.6a2c432d6a40bp-44, -0x1.f1e7cf6d3a69cp-50,
    0x1.eb1245b5da1f5p-44, -0x1.9e23f0dda40e4p-46, -0x1.0bc04a086b56ap-45,
    0x0.0p+0, 0x1.166afcb31c67bp-45, 0x1.bce251998b506p-44,
    0x1.4554412c584e0p-44, 0x1.611d27c8e8417p-44, 0x1.98139928637fep-47,
    0x1.b4a690fe94778p-48, 0x1.8e611b8afbfe8p-46, 0x1.42ad9271be7d7p-45,
    0x1.a9cc78d8df999p-44, 0x1.8357d5ef9eb35p-44, -0x1.8888ddfc47628p-44,
    -0x1.08b0d083b3a4cp-46, -0x1.9d7c53f76ca96p-46, 0x1.d5674d6cf558ep-44,
    -0x1.3c85d2a29bbd6p-44, 0x1.c3dd83606d891p-44, -0x1.7e5dd7009902cp-46,
    -0x1.9bb2907030829p-47, 0x1.b4bac097c5ba3p-47, -0x1.692b6a81b8848p-49,
    0x1.fad46e8d26ab7p-44, 0x1.30a1d96258b3ep-44, 0x1.1cb7ce1d17171p-44,
    0x1.c1e8da99ded32p-49, 0x1.3c88c3e706706p-44, 0x1.c28c0af9bd6dfp-44,
    -0x1.ab7c09e838668p-44, 0x1.e63794c02c4afp-44, 0x1.b1bdff50225c7p-44,
    0x1.cb1121d1930ddp-44, 0x1.0e239cc185469p-44, 0x1.0f684e6766abdp-45,
    0x1.2e31f6c272c1ep-44, 0x1.56594d82f7a82p-44, 0x1.6304628340ee9p-44,
    0x1.4652dabff5447p-46, -0x1.cf5fdd94f6509p-45, -0x1.1ac38dde3b366p-44,
    -0x1.b3a1e7f50c701p-44, 0x1.7494e359302e6p-44, 0x1.52b302160f40dp-44,
    -0x1.fd3a0afb9691bp-44, 0x1.3fb2f85096c4bp-46, -0x1.84858a711b062p-44,
    0x1.522ecf56e7952p-46, -0x1.4e60b8d4b411dp-44, -0x1.a1d059769ca05p-44,
    -0x1.71456c988f814p-44, -0x1.11e8830a706d3p-44, -0x1.c73fafd9b2dcap-50,
    -0x1.d66a90d0005a6p-44, -0x1.ae75fcb067e57p-44, 0x1.e0ddb9a631e83p-46,
    0x1.328eb42f9af75p-44, 0x1.b7d5cab2d1140p-44, 0x1.7f22858a0ff6fp-47,
    0x1.470fa3efec390p-44, -0x1.01e0f004f3781p-44, -0x1.8724350562169p-45,
    0x1.7a8d5ae54f550p-44, 0x1.9b50e83aa91dfp-44, -0x1.d4bc4595412b6p-45,
    -0x1.92e0ee55c7ac6p-45, 0x1.3b161a8c6e6c5p-45, -0x1.9e0aba2099515p-45,
    -0x1.5d6e06fc20d39p-44, 0x1.2806a847527e6p-44, 0x1.823817787081ap-44,
    -0x1.d5eee23793649p-47, -0x1.a211565bb8e11p-51, -0x1.bae49f1df7b5ep-44,
    0x1.4bba46f1cf6a0p-44, 0x1.1cd8d688b9e18p-44, 0x1.dbdf10d397f3cp-45,
    -0x1.e76324e912b17p-44, 0x1.b50a1e1734342p-44, 0x1.ee8c88753fa35p-46,
    -0x1.f1fbddfdfd686p-45, 0x1.3b2948a11f797p-46, -0x1.23299042d74bfp-44,
    0x1.7d2f73ad1aa14p-45, -0x1.1ac89575c2125p-44, 0x1.e9d5b513ff0c1p-44,
    -0x1.a1421609580dap-44, 0x1.b1d7ac0ef77f2p-44, -0x1.b198800b4bda7p-45,
    0x1.a9cfa4a5004f4p-45, 0x1.4300c128d1dc2p-45, -0x1.8e27ad3213cb8p-45,
    -0x1.17c73556e291dp-44, -0x1.a71e493a0702bp-45, -0x1.d0befbc02be4ap-45,
    -0x1.22c7c2a9d37a4p-45, 0x1.e6ef574487308p-44, 0x1.906440f7d3354p-44,
    -0x1.d9120e7d0a853p-47, 0x1.dc1b8465cf25fp-44, -0x1.65b4681052b9fp-46,
    -0x1.fc158cb3124b9p-44, 0x1.ebe708164c759p-45, 0x1.a8954c0910952p-46,
    0x1.fadedee5d40efp-46, -0x1.7c79b0af7ecf8p-48, -0x1.a0b2a08a465dcp-47,
    0x1.ebe9176df3f65p-46, -0x1.db623e731ae00p-45,
};
static const double chaplygin_dm_LOG_POLY[6] = {
    -0x1.0000000000000p-1, 0x1.5555555555555p-2, -0x1.0000000000000p-2,
    0x1.999999999999ap-3, -0x1.5555555555555p-3, 0x1.2492492492492p-3,
};
static const double chaplygin_dm_LOGDD_POLY[6] = {
    0x1.5555555555555p-2, -0x1.0000000000000p-2, 0x1.999999999999ap-3,
    -0x1.5555555555555p-3, 0x1.2492492492492p-3, -0x1.0000000000000p-3,
};
static const double chaplygin_dm_LOG2_K_HI = 0x1.71547652b82fep+0;
static const double chaplygin_dm_LOG2_K_LO = 0x1.777d0ffda0d24p-56;
static const double chaplygin_dm_LOG2_E_HI = 0x1.0000000000000p+0;
static const double chaplygin_dm_LOG2_E_LO = 0x0.0p+0;
static const double chaplygin_dm_LOG2_L_HI[182] = {
    -0x1.ffd799a840000p-2, -0x1.f7a8568cb0000p-2, -0x1.ef6d67328e000p-2,
    -0x1.e8302829a6000p-2, -0x1.dfdefb29cf000p-2, -0x1.d781c01f9a000p-2,
    -0x1.d0262d5540000p-2, -0x1.c7b1f8c4f5000p-2, -0x1.c04214498b000p-2,
    -0x1.b8c88dbf88000p-2, -0x1.b031befe06000p-2, -0x1.a8a33f17b4000p-2,
    -0x1.a10acd0096000p-2, -0x1.99684e676a000p-2, -0x1.91bba891f1000p-2,
    -0x1.8a04c05abc000p-2, -0x1.835fba098c000p-2, -0x1.7b957ac51b000p-2,
    -0x1.73c0a92c6a000p-2, -0x1.6d01becaca000p-2, -0x1.6518fe4678000p-2,
    -0x1.5e48d25f63000p-2, -0x1.564bbc7149000p-2, -0x1.4f69f5d830000p-2,
    -0x1.487ff067f1000p-2, -0x1.418d98469e000p-2, -0x1.39683c4a9d000p-2,
    -0x1.32639636b3000p-2, -0x1.2b565cb331000p-2, -0x1.24407ab0e0000p-2,
    -0x1.1d21dad295000p-2, -0x1.172c43298e000p-2, -0x1.0ffd6407e8000p-2,
    -0x1.08c588cda8000p-2, -0x1.01849ae488000p-2, -0x1.f6e4565680000p-3,
    -0x1.e840be74e6000p-3, -0x1.d98a7d8a60000p-3, -0x1.cd398e83e8000p-3,
    -0x1.c0db6cdd94000p-3, -0x1.b1f27d7bd8000p-3, -0x1.a576ee5f30000p-3,
    -0x1.98edd077e8000p-3, -0x1.89d0d0ab44000p-3, -0x1.7d29766136000p-3,
    -0x1.70742d4ef0000p-3, -0x1.63b0d6a3e4000p-3, -0x1.56df5328d6000p-3,
    -0x1.49ff833e16000p-3, -0x1.3d1146d9a8000p-3, -0x1.30147d856c000p-3,
    -0x1.2309065d2a000p-3, -0x1.15eec00ca8000p-3, -0x1.08c588cda8000p-3,
    -0x1.fc66a0f0b0000p-4, -0x1.e1ddbb9110000p-4, -0x1.c73632513c000p-4,
    -0x1.ac6fbe1c30000p-4, -0x1.96edbac9c8000p-4, -0x1.7beee96b8c000p-4,
    -0x1.663f6fac90000p-4, -0x1.4b0751e058000p-4, -0x1.35299fe94c000p-4,
    -0x1.19b74069f4000p-4, -0x1.03aa8f8dc8000p-4, -0x1.db11751610000p-5,
    -0x1.a380eecfc0000p-5, -0x1.76dcf723a8000p-5, -0x1.4a0dab4578000p-5,
    -0x1.1d12b6c688000p-5, -0x1.c9363ba850000p-6, -0x1.6e79685c30000p-6,
    -0x1.1363117a90000p-6, -0x1.6fe50b6f00000p-7, -0x1.709c46d7c0000p-8,
    0x0.0p+0, 0x1.720d9c06c0000p-8, 0x1.72c7ba2100000p-7,
    0x1.16a21e20a0000p-6, 0x1.743ee861f0000p-6, 0x1.d23afc4910000p-6,
    0x1.0c7b844ef0000p-5, 0x1.3bcdd9b9f0000p-5, 0x1.6b50e297b0000p-5,
    0x1.9b05038d88000p-5, 0x1.beec9151a8000p-5, 0x1.eef7925088000p-5,
    0x1.0f9a634664000p-4, 0x1.21c1ef55f0000p-4, 0x1.3a0cf56a08000p-4,
    0x1.5271a78624000p-4, 0x1.64ce26c068000p-4, 0x1.7d60496cfc000p-4,
    0x1.8fdf1ca8f0000p-4, 0x1.a89f5a6dc8000p-4, 0x1.bb4102f924000p-4,
    0x1.d4300a2524000p-4, 0x1.e6f50c2da0000p-4, 0x1.f9c95dc1d0000p-4,
    0x1.097e38ce60000p-3, 0x1.12fa6f5510000p-3, 0x1.1c7e77dde4000p-3,
    0x1.293ac3dc1a000p-3, 0x1.32d13e4692000p-3, 0x1.3c6fb650ce000p-3,
    0x1.46163957b0000p-3, 0x1.5300d796e0000p-3, 0x1.5cba53a076000p-3,
    0x1.667c08270c000p-3, 0x1.7046031c7a000p-3, 0x1.7a18529636000p-3,
    0x1.83f304cdc6000p-3, 0x1.8dd6282140000p-3, 0x1.97c1cb13c8000p-3,
    0x1.a1b5fc4e0c000p-3, 0x1.abb2ca9ec8000p-3, 0x1.b5b844fb4c000p-3,
    0x1.bfc67a8000000p-3, 0x1.c9dd7a70ee000p-3, 0x1.d3fd543a4a000p-3,
    0x1.de26177108000p-3, 0x1.e857d3d362000p-3, 0x1.f29299496a000p-3,
    0x1.fcd677e5ac000p-3, 0x1.0391bff2dc000p-2, 0x1.070352293d000p-2,
    0x1.0c318aedff000p-2, 0x1.11646e7791000p-2, 0x1.169c05363f000p-2,
    0x1.1a190a5d67000p-2, 0x1.1f588973c8000p-2, 0x1.249cd2b13d000p-2,
    0x1.28225bb5e6000p-2, 0x1.2d6eb41523000p-2, 0x1.32bfee370f000p-2,
    0x1.364e2511cd000p-2, 0x1.3ba7963fc2000p-2, 0x1.4106017c3f000p-2,
    0x1.449d115ef8000p-2, 0x1.4a03dcbd2e000p-2, 0x1.4da08ac465000p-2,
    0x1.530fd08f2a000p-2, 0x1.56b22e6b58000p-2, 0x1.5c2a096a13000p-2,
    0x1.5fd2291fc3000p-2, 0x1.6552b49986000p-2, 0x1.6900a8836d000p-2,
    0x1.6e8a004222000p-2, 0x1.723ddb1347000p-2, 0x1.77d01b66fc000p-2,
    0x1.7b89f02cf3000p-2, 0x1.7f462e58e1000p-2, 0x1.84e5181475000p-2,
    0x1.88a76b7e55000p-2, 0x1.8c6c335d8c000p-2, 0x1.921800924e000p-2,
    0x1.95e2f9b51f000p-2, 0x1.99b072a96c000p-2, 0x1.9f695efbbd000p-2,
    0x1.a33d25fcb2000p-2, 0x1.a713787ad9000p-2, 0x1.aaec59dadb000p-2,
    0x1.b0b67f4f47000p-2, 0x1.b495d4e918000p-2, 0x1.b877c57b1b000p-2,
    0x1.bc5c548925000p-2, 0x1.c2381c08bb000p-2, 0x1.c62346dca2000p-2,
    0x1.ca111cb2aa000p-2, 0x1.ce01a12f5e000p-2, 0x1.d1f4d7fec0000p-2,
    0x1.d5eac4d464000p-2, 0x1.d9e36b6b82000p-2, 0x1.dddecf870c000p-2,
    0x1.e3dd115650000p-2, 0x1.e7df5fe539000p-2, 0x1.ebe47960e4000p-2,
    0x1.efec61b012000p-2, 0x1.f3f71cc1b6000p-2, 0x1.f804ae8d0d000p-2,
    0x1.fc151b11b3000p-2, 0x1.0014332be0000p-1,
};
static const double chaplygin_dm_LOG2_L_LO[182] = {
    0x1.9518ce032f41dp-48, -0x1.b3b3864c60011p-44, -0x1.103e8f00d41c8p-45,
    -0x1.79ec9d8efda9cp-47, -0x1.5c3675f82da80p-47, 0x1.19e47623ddf37p-45,
    -0x1.46fab3fa1a144p-44, -0x1.a3f6c066ebdd5p-46, -0x1.77a42f5fc4f1ep-44,
    -0x1.9e65cd77582e2p-44, -0x1.0d199805b0aecp-44, -0x1.0ad35665e0e32p-44,
    0x1.52e8978a6cc8ap-44, 0x1.342b98d0710f5p-48, -0x1.c22d2cad415aep-44,
    0x1.aa4a112bff53ep-44, 0x1.d30543c5b34f0p-46, 0x1.4eea27240b049p-44,
    -0x1.317bdec192554p-45, 0x1.0c553ee1c9f2fp-46, 0x1.1646b761c48dep-44,
    0x1.51a6bb8ad2771p-44, 0x1.c0993c8ee9c80p-44, -0x1.8f36dd24bae46p-44,
    -0x1.0dde7aeac72f7p-45, 0x1.05104ded813f7p-44, 0x1.664deafdbfed5p-46,
    0x1.f29947070fc4bp-44, -0x1.dafbfd96d5335p-45, -0x1.ce60916e52e91p-44,
    -0x1.8c9a2f2dbcaf9p-44, -0x1.6d1b218191084p-44, 0x1.38f6f7da54e93p-44,
    0x1.871a7610e40bdp-44, -0x1.fa1f67cf926cbp-45, 0x1.aaa72ba2c6ba2p-47,
    -0x1.4998f93e7aa3cp-44, -0x1.69affffe47644p-45, -0x1.5f5cde492c839p-47,
    -0x1.bdc81c4db3134p-44, 0x1.601ccfac2b557p-45, 0x1.3c4700aaa0694p-46,
    0x1.e41fa0a62e6aep-44, 0x1.e665e245fe368p-44, 0x1.ace3c5d64cd75p-46,
    -0x1.3f94e00e7d6bcp-46, 0x1.aea762b075027p-45, 0x1.cea9347cb6655p-45,
    0x1.03d7c29e51687p-44, -0x1.4c7e0166e1f56p-44, 0x1.72c3855fc4925p-45,
    0x1.0dd830ee74ef2p-44, 0x1.0d9aaa3b48fe9p-45, 0x1.871a7610e40bdp-45,
    -0x1.49209a68c72a1p-49, 0x1.ffa2f757bbacbp-45, 0x1.58b34834a501ep-47,
    0x1.99a5ff389880fp-44, 0x1.a9d6325d9ee57p-44, 0x1.d7ec3be51cdcbp-44,
    -0x1.3167ccc538261p-44, 0x1.29fa3791d16b0p-45, 0x1.0a1979c9b774bp-45,
    -0x1.f09941811b2eep-44, -0x1.53121e9af5428p-46, 0x1.8a0e14f76d994p-46,
    0x1.f38b72c9d8e90p-44, -0x1.a34c2beb0ade0p-44, 0x1.f831808f99b51p-44,
    0x1.3a7ad6c182ca9p-49, -0x1.f0cccdd01ee2fp-47, 0x1.6eb3ac8ec0ef7p-45,
    -0x1.ec312ed069b24p-44, 0x1.ef5d00e390a00p-44, 0x1.5388b52642db7p-44,
    0x0.0p+0, -0x1.7ca15910e7069p-44, -0x1.19b14945cf6bap-44,
    0x1.48a179268271dp-47, 0x1.aab1b2a41b090p-45, 0x1.cfc4de6d73deap-45,
    0x1.794d4c6c8f327p-45, 0x1.e66be73b9da04p-50, -0x1.98fd2dca61c14p-48,
    -0x1.fb554647678d1p-44, 0x1.61728d82263edp-44, 0x1.b4eb09b992dcep-44,
    -0x1.48cd0a7bb24b2p-46, 0x1.b08127eec65d2p-46, -0x1.3b55bcb161bacp-44,
    -0x1.5f097b0fe80a3p-44, -0x1.d5297837adb4bp-45, -0x1.2ce6312ebb81dp-46,
    -0x1.595f2f68d91fdp-44, 0x1.acbebd7e444ecp-44, 0x1.393c664ed16b7p-44,
    0x1.a82ed66976b91p-45, -0x1.15844900583dep-45, 0x1.164e932b2d51cp-44,
    0x1.924ae921f7ecap-45, -0x1.da89e835cc3d2p-45, -0x1.848e9d1d92d88p-44,
    0x1.9a1979619fe2fp-45, 0x1.d6d57e540628ep-44, -0x1.af5e9bb5386c2p-47,
    -0x1.fa4a9eb6b8621p-44, -0x1.98cc3b5d08e15p-44, 0x1.769a8e6b40f5ep-46,
    -0x1.bebde1ac6e983p-45, -0x1.ed0798d1aa217p-49, -0x1.b6967f02b01d8p-45,
    -0x1.5651ccd0e0880p-45, 0x1.2a424c693063dp-45, -0x1.3f7a55cd2af4cp-47,
    -0x1.73647bf25fa5fp-44, -0x1.71b3a63cddadfp-44, -0x1.821d36e0b7548p-44,
    -0x1.667f21fa8423fp-44, -0x1.d400fd651da9ap-44, 0x1.ab8f49b9239d6p-44,
    0x1.a06e2b9b128bfp-44, -0x1.9308437e74325p-44, 0x1.11159ca9c9783p-44,
    0x1.039b772eda08ep-44, -0x1.866405210e49ep-45, 0x1.c91a3dbbb501dp-44,
    0x1.e03b336c24b74p-45, 0x1.1a55c2b07d3a5p-44, 0x1.5872350f805d6p-46,
    0x1.281a3174c8d06p-44, 0x1.d1c61f4accdd7p-44, -0x1.49d97df07e357p-45,
    0x1.28fa3aac2fde9p-44, 0x1.27ae8037b21bfp-45, -0x1.979a5db68721dp-46,
    -0x1.f7cc3df8803d1p-44, -0x1.c4413fd83dec1p-48, -0x1.aeb8cb1ac05cdp-45,
    -0x1.3c49c247ab6afp-45, 0x1.bdc90791aef03p-46, -0x1.a96d7a36f1545p-44,
    -0x1.63d8bd35fdc18p-48, -0x1.c6d8d86531d56p-44, 0x1.770d330890c82p-44,
    0x1.e77ad7a4b71c0p-45, 0x1.3bb5921006679p-45, 0x1.aa0e9e6bca777p-47,
    -0x1.3859a74f0d148p-44, -0x1.26baaf0b591f8p-44, -0x1.64adb1adca9a8p-45,
    -0x1.54b383b0e8a55p-44, 0x1.a20a0968271abp-44, 0x1.123e24ebf7a85p-44,
    -0x1.8e9b57298d22fp-44, -0x1.a69393bab4fd0p-44, -0x1.62404772a151dp-45,
    0x1.38bc99b3611cep-48, 0x1.ac9bca36fd02ep-44, 0x1.dd3d30f5deaa7p-47,
    -0x1.4f144da6e4533p-48, 0x1.e92e07396497fp-44, -0x1.2100986691daap-45,
    -0x1.fc02bc277071dp-44, 0x1.7dd4bcb97f73cp-44, 0x1.bfbf899cf2b3cp-48,
    0x1.32e75785e97abp-44, -0x1.62c45c4bc31c9p-47, -0x1.012f1593ee62ap-45,
    0x1.7150fe371d52bp-44, -0x1.cbb828084fcb1p-44, -0x1.e6009faee4be8p-44,
    -0x1.410f5d3161a62p-45, 0x1.6c28f5a9b58fdp-44, 0x1.305af9767a020p-44,
    0x1.f77628aa1aed8p-44, -0x1.532c412ba94dbp-44, -0x1.fbc00d8d6cbcfp-45,
    -0x1.ea92d9e0e8ac2p-48, 0x1.4dc166e0e0c68p-45, -0x1.7f33943464056p-45,
    0x1.9006e6a042173p-44, 0x1.9518ce032f41dp-48,
};
static const double chaplygin_dm_LOG2_POLY[6] = {
    -0x1.71547652b82fep-1, 0x1.ec709dc3a03fdp-2, -0x1.71547652b82fep-2,
    0x1.2776c50ef9bfep-2, -0x1.ec709dc3a03fdp-3, 0x1.a61762a7aded9p-3,
};
static const double chaplygin_dm_LOG10_K_HI = 0x1.bcb7b1526e50ep-2;
static const double chaplygin_dm_LOG10_K_LO = 0x1.95355baaafad3p-57;
static const double chaplygin_dm_LOG10_E_HI = 0x1.34413509f7800p-2;
static const double chaplygin_dm_LOG10_E_LO = 0x1.fef311f12b358p-46;
static const double chaplygin_dm_LOG10_L_HI[182] = {
    -0x1.3428e25401000p-3, -0x1.2f3b691c5a000p-3, -0x1.2a46e8ca7c000p-3,
    -0x1.25eb24d8a4000p-3, -0x1.20e9409bf6000p-3, -0x1.1be01a6403000p-3,
    -0x1.1772143307000p-3, -0x1.125b18f35c000p-3, -0x1.0de0d70762000p-3,
    -0x1.0960c8648e000p-3, -0x1.0434f7fb1f000p-3, -0x1.ff509155de000p-4,
    -0x1.f62b38ca3a000p-4, -0x1.ecf9c6a2dc000p-4, -0x1.e3bc1ab0e2000p-4,
    -0x1.da72144454000p-4, -0x1.d271d763a0000p-4, -0x1.c910874e0a000p-4,
    -0x1.bfa27c79c0000p-4, -0x1.b783129d00000p-4, -0x1.adfd07416c000p-4,
    -0x1.a5c8d62ae4000p-4, -0x1.9c2a4ede26000p-4, -0x1.93e0eb2d86000p-4,
    -0x1.8b8d99c860000p-4, -0x1.833042c776000p-4, -0x1.79613cefdc000p-4,
    -0x1.70eddb7d7e000p-4, -0x1.68702679aa000p-4, -0x1.5fe80488b0000p-4,
    -0x1.57555bf108000p-4, -0x1.50285ce216000p-4, -0x1.47822409f6000p-4,
    -0x1.3ed1199a5e000p-4, -0x1.36152260c2000p-4, -0x1.2ec568056c000p-4,
    -0x1.25f5215eb6000p-4, -0x1.1d199ea83c000p-4, -0x1.15af5d5162000p-4,
    -0x1.0e3d29d812000p-4, -0x1.054323b97a000p-4, -0x1.fb7e714f14000p-5,
    -0x1.ec6647eb58000p-5, -0x1.da338aaa98000p-5, -0x1.caf6f8ec70000p-5,
    -0x1.bba9a058e0000p-5, -0x1.ac4b5bd524000p-5, -0x1.9cdc05cad4000p-5,
    -0x1.8d5b7825c4000p-5, -0x1.7dc98c51c8000p-5, -0x1.6e261b3878000p-5,
    -0x1.5e70fd3ee8000p-5, -0x1.4eaa0a433c000p-5, -0x1.3ed1199a60000p-5,
    -0x1.32167c82bc000p-5, -0x1.221cc16668000p-5, -0x1.121093ce3c000p-5,
    -0x1.01f1c8ee80000p-5, -0x1.e9fdab6640000p-6, -0x1.c97c3735e8000p-6,
    -0x1.af5f92b010000p-6, -0x1.8e991ff318000p-6, -0x1.7444d403f0000p-6,
    -0x1.53383b64c0000p-6, -0x1.38ab58d170000p-6, -0x1.1e05015d30000p-6,
    -0x1.f921f9f890000p-7, -0x1.c361551c00000p-7, -0x1.8d6c83e9c0000p-7,
    -0x1.574320b740000p-7, -0x1.1344daa2d0000p-7, -0x1.b9476a4fc0000p-8,
    -0x1.4b99563d20000p-8, -0x1.bafd472200000p-9, -0x1.bbd9e94800000p-10,
    0x0.0p+0, 0x1.bd96a1d800000p-10, 0x1.be76bd77c0000p-9,
    0x1.4f82052360000p-8, 0x1.c03a80ae60000p-8, 0x1.18b2dc8d30000p-7,
    0x1.4348fe2ba0000p-7, 0x1.7c441aa5e0000p-7, 0x1.b579db6df0000p-7,
    0x1.eeeab9b430000p-7, 0x1.0d133abfc0000p-6, 0x1.29fff7b8c8000p-6,
    0x1.470aede970000p-6, 0x1.5ce7223998000p-6, 0x1.7a27959ec8000p-6,
    0x1.9786f287a0000p-6, 0x1.ada2e8e3e8000p-6, 0x1.cb38fccd88000p-6,
    0x1.e17e48fa48000p-6, 0x1.ff4be13b90000p-6, 0x1.0add8f759c000p-5,
    0x1.19e086b3b8000p-5, 0x1.252d6de158000p-5, 0x1.30838cdc30000p-5,
    0x1.3faf7c6630000p-5, 0x1.4b1b588128000p-5, 0x1.56909f44a8000p-5,
    0x1.65e6692548000p-5, 0x1.7171e59efc000p-5, 0x1.7d070145f4000p-5,
    0x1.88a5cc3158000p-5, 0x1.98335cd4a0000p-5, 0x1.a3e9002c70000p-5,
    0x1.afa88992b0000p-5, 0x1.bb7209d1e4000p-5, 0x1.c74591df74000p-5,
    0x1.d32332dc34000p-5, 0x1.df0afe1504000p-5, 0x1.eafd05035c000p-5,
    0x1.f6f9594de8000p-5, 0x1.0180066492000p-4, 0x1.078898bc06000p-4,
    0x1.0d966cc650000p-4, 0x1.13a98bb450000p-4, 0x1.19c1fecf18000p-4,
    0x1.1fdfcf783a000p-4, 0x1.2603072a26000p-4, 0x1.2c2baf7882000p-4,
    0x1.3259d2107e000p-4, 0x1.388d78b936000p-4, 0x1.3cb2fd2f68000p-4,
    0x1.42efeb4b50000p-4, 0x1.4932780c56000p-4, 0x1.4f7aad9bbc000p-4,
    0x1.53adfb462c000p-4, 0x1.59ffb662b8000p-4, 0x1.605735ee98000p-4,
    0x1.6494c46ac6000p-4, 0x1.6af5f838d0000p-4, 0x1.715d0ce368000p-4,
    0x1.75a50ebb16000p-4, 0x1.7c1607b7d8000p-4, 0x1.828cfed29a000p-4,
    0x1.86dfa808d4000p-4, 0x1.8d60b4ee4e000p-4, 0x1.91ba21d6be000p-4,
    0x1.9845642fac000p-4, 0x1.9ca5aa172a000p-4, 0x1.a33b422246000p-4,
    0x1.a7a276bade000p-4, 0x1.ae4285509a000p-4, 0x1.b2b0beb41a000p-4,
    0x1.b95b654a78000p-4, 0x1.bdd0b9fd0a000p-4, 0x1.c4861aab94000p-4,
    0x1.c902a19e66000p-4, 0x1.cd820ffd28000p-4, 0x1.d446afb64c000p-4,
    0x1.d8cd71303c000p-4, 0x1.dd5727676c000p-4, 0x1.e42b4c16ca000p-4,
    0x1.e8bc77271c000p-4, 0x1.ed50a4a26e000p-4, 0x1.f4349618fa000p-4,
    0x1.f8d05b16a6000p-4, 0x1.fd6f308ce6000p-4, 0x1.01088d48d7000p-3,
    0x1.0484e4942b000p-3, 0x1.06d9bc53c3000p-3, 0x1.093025a199000p-3,
    0x1.0b88229b71000p-3, 0x1.0f0f17a062000p-3, 0x1.116b0f26b6000p-3,
    0x1.13c8a1e34f000p-3, 0x1.1627d2079e000p-3, 0x1.1888a1c996000p-3,
    0x1.1aeb1363b4000p-3, 0x1.1d4f291514000p-3, 0x1.1fb4e52174000p-3,
    0x1.23509c1e6e000p-3, 0x1.25ba8215af000p-3, 0x1.2826167a6c000p-3,
    0x1.2a935ba5f1000p-3, 0x1.2d0253f67e000p-3, 0x1.2f7301cf4f000p-3,
    0x1.31e56798a9000p-3, 0x1.345987bfef000p-3,
};
static const double chaplygin_dm_LOG10_L_LO[182] = {
    0x1.a4b127307ee7bp-45, -0x1.7c697e103ceaap-56, 0x1.759aa8c8a1f1cp-45,
    -0x1.25b850410c345p-45, 0x1.1ba8a98ead129p-46, 0x1.c515566ba1d49p-46,
    0x1.1d11989e19961p-46, 0x1.1c840d7cad4afp-45, -0x1.dc74701a04ae8p-46,
    -0x1.01962350c9786p-45, -0x1.835fff5aa0d20p-46, -0x1.c3cab7f7fe01ep-46,
    -0x1.c16ecb7c4c7d8p-46, -0x1.5b647cb08b012p-45, 0x1.8070aa756b03ep-46,
    0x1.4264f641f6863p-47, 0x1.636cbc923a220p-45, 0x1.9e51edfb93e55p-50,
    -0x1.80b25f46af414p-46, 0x1.dcfd0b415e812p-45, 0x1.f902891596119p-48,
    0x1.0a1a7adda1ce4p-47, 0x1.4c0f0f0ce2075p-47, 0x1.a6e844a5aee94p-45,
    0x1.e6323527d3cf1p-46, 0x1.7dfc0e2cd5d51p-45, -0x1.f5738f0e65429p-50,
    -0x1.40ec5f6c004c6p-45, 0x1.fd7f163d5205ep-46, 0x1.606adb567e739p-45,
    0x1.016119abf2df8p-45, 0x1.59e930b22214dp-45, 0x1.0d7dc18a264f4p-45,
    -0x1.0940dd49f5d1fp-46, -0x1.8a96e451a1f07p-45, -0x1.6e95635907534p-48,
    0x1.ad88356812e52p-46, 0x1.07165a9c258d4p-50, 0x1.9da6cf2627ad2p-45,
    0x1.3433b54d3ce1cp-45, -0x1.28f81f24acfecp-45, 0x1.e8ba01f12fb69p-50,
    -0x1.0108fa031185ap-46, -0x1.4173b2a06eb58p-46, -0x1.d2795f2aaf6b2p-50,
    0x1.3df2b4349e5dcp-48, 0x1.bedf14a085897p-46, -0x1.07abf77f1bb28p-51,
    0x1.6c5f7503f8b10p-51, -0x1.2127595668247p-48, -0x1.379694bbd6602p-45,
    0x1.4cc1c6bf68db0p-45, -0x1.03dcce63aacc6p-45, 0x1.bdafc8ad828b8p-45,
    -0x1.cd99b51b6b847p-45, -0x1.3744450422bb0p-47, 0x1.dfb090257a126p-45,
    0x1.280a7f4bc1b6bp-45, 0x1.00132ce78de0fp-47, 0x1.fae091a402ecdp-49,
    0x1.9f05921f59258p-46, -0x1.4591bc98a50b1p-45, -0x1.54a37469c70a3p-47,
    0x1.d82564e0ad4cep-47, -0x1.f4853edba0639p-45, -0x1.4e241ecdd26bfp-47,
    -0x1.f3675e978d3f9p-45, -0x1.a7e2de20d348cp-47, 0x1.623d63ac84fd2p-45,
    0x1.683a23a29bb9ap-46, -0x1.d54a6c7cafdc7p-45, -0x1.a21db136b482ep-45,
    -0x1.437a1fb495d64p-45, -0x1.ed2665c1ba949p-45, -0x1.5784564411e70p-45,
    0x0.0p+0, -0x1.31a1eb97093b9p-45, -0x1.6079e5269431bp-46,
    -0x1.dfa6d47e47379p-45, -0x1.fac7d2ae08e4fp-48, -0x1.11bc6f2b9a3acp-45,
    -0x1.bff60d297cc02p-45, 0x1.b4533966c4829p-45, -0x1.e53d804133fedp-46,
    0x1.1173041d3dfabp-45, 0x1.f8d484ac7f8e4p-45, 0x1.3ce96210c78e1p-45,
    -0x1.80e1fcdb87b8cp-46, 0x1.72f6688a56bb4p-47, 0x1.1a9d2d3ef0b9dp-46,
    -0x1.d651a345db748p-49, -0x1.5c85cc3231fcdp-45, 0x1.fedb4b594a31bp-45,
    0x1.2c45f4fe4cd29p-47, 0x1.48fd764dea1d9p-45, 0x1.b2a51090000a1p-46,
    0x1.99ac1fd443e40p-48, -0x1.b3f6a1447d572p-45, -0x1.00c12f7a1b586p-47,
    0x1.83662f181f53fp-47, 0x1.20287dac177e6p-45, -0x1.a04483513cf5bp-46,
    -0x1.d8cf527f38ac6p-48, 0x1.6bd1a3fcf54dbp-46, 0x1.fae96a708581ep-46,
    0x1.e533f553fef1cp-45, 0x1.6c2c0931d0032p-45, 0x1.1d257c8d0d386p-45,
    -0x1.5e6edad46beacp-45, -0x1.b1aad42a57f54p-45, -0x1.baa2ac97e1b3ap-45,
    0x1.b7adbf8d9441fp-46, 0x1.7380ccaaf85cdp-45, -0x1.626d2c723bf3bp-48,
    -0x1.f0f9c4cf885d9p-45, 0x1.02e6fe745fe1bp-45, -0x1.02ec636ff5e31p-46,
    0x1.f3735158d42c3p-49, 0x1.f0168af5d72d9p-45, -0x1.1fc0e1acaa2c7p-48,
    -0x1.ff1c0edf108fap-46, -0x1.f74be7c4de292p-50, -0x1.0928e7edddb07p-45,
    -0x1.2ae2d46660d9ap-46, -0x1.e02a454f533f9p-45, -0x1.0f6d74f54f373p-48,
    0x1.ba270494ee73dp-46, 0x1.fc4accd62a5f3p-45, 0x1.75da8a5871b9ap-45,
    0x1.c2c6f11e3581cp-45, 0x1.5bcd1450d31d8p-48, 0x1.7c3cf23a17d9fp-46,
    0x1.c9ad68b9c6cb5p-45, -0x1.358b67f75a3d9p-45, -0x1.41149840eaa65p-46,
    0x1.251e4ba167ee7p-47, -0x1.cdee31de0d912p-48, 0x1.0a581f3edc493p-47,
    -0x1.2c09bb60238bap-45, -0x1.bfc68cec6cdf8p-46, 0x1.eee43c433a6e8p-45,
    0x1.1e0d4cb374e10p-45, -0x1.76b169f6b4949p-49, -0x1.21d1f97315195p-45,
    -0x1.a70c2cd506c59p-45, -0x1.5e950adf89934p-45, -0x1.4bf54bb10eca6p-46,
    0x1.90e5e24764ec7p-45, -0x1.7c0f454116be6p-46, -0x1.775b6b51fca7bp-46,
    -0x1.ddd18dedb6656p-45, -0x1.c358f377e27bcp-46, 0x1.f95fec4153145p-46,
    -0x1.6d13f77d50b7ap-47, 0x1.2b2443f2d9850p-45, 0x1.5e50ff38d4de9p-45,
    -0x1.a197240569ddfp-46, 0x1.5f7ef576ada0cp-45, 0x1.2330dc1d0b46fp-45,
    0x1.a8ea5a2b777a7p-45, -0x1.2b807fe49ef2cp-46, -0x1.fd52fa710edd5p-47,
    -0x1.6f30673aae7efp-45, -0x1.afce4223c0b76p-45, 0x1.dae5ed5e3f34cp-45,
    0x1.135ecffdd160fp-46, 0x1.a9547d2cbfbb2p-46, 0x1.eeb24143ef26bp-45,
    0x1.e80b5412d1511p-45, 0x1.cc5153fe60877p-45, -0x1.b3c1301ae9ac8p-45,
    0x1.3219d92f934ccp-45, -0x1.fed10b114338bp-47, 0x1.e7216e57e6c06p-48,
    -0x1.b2215ab3ec84fp-45, 0x1.ff081a4e81f0bp-45, -0x1.b1d5505664200p-46,
    0x1.1e3f04f63ee01p-45, 0x1.32ac22596b4a0p-45, -0x1.e1471e5cb397ep-45,
    0x1.0a296f3a32aecp-47, -0x1.5bd54fd6eb7d9p-45,
};
static const double chaplygin_dm_LOG10_POLY[6] = {
    -0x1.bcb7b1526e50ep-3, 0x1.287a7636f435fp-3, -0x1.bcb7b1526e50ep-4,
    0x1.63c62775250d8p-4, -0x1.287a7636f435fp-4, 0x1.fc3fa615105c7p-5,
};
static const double chaplygin_dm_SIN_POLY[5] = {
    -0x1.5555555555555p-3, 0x1.1111111111111p-7, -0x1.a01a01a01a01ap-13,
    0x1.71de3a556c734p-19, -0x1.ae64567f544e4p-26,
};
static const double chaplygin_dm_COS_POLY[5] = {
    -0x1.0000000000000p-1, 0x1.5555555555555p-5, -0x1.6c16c16c16c17p-10,
    0x1.a01a01a01a01ap-16, -0x1.27e4fb7789f5cp-22,
};
static const double chaplygin_dm_SIND_POLY[2] = {
    -0x1.5555555555555p-3, 0x1.1111111111111p-7,
};
static const double chaplygin_dm_COSD_POLY[3] = {
    -0x1.0000000000000p-1, 0x1.5555555555555p-5, -0x1.6c16c16c16c17p-10,
};
static const double chaplygin_dm_TRIG_S_HI[86] = {
    0x1.feaaeee86ee36p-4, 0x1.0f3378ddd71d1p-3, 0x1.1f0d3d7afceafp-3,
    0x1.2ee285e4ab88fp-3, 0x1.3eb312c5d66cbp-3, 0x1.4e7ea4dc5f27bp-3,
    0x1.5e44fcfa126f3p-3, 0x1.6e05dc05a4d4cp-3, 0x1.7dc102fbaf2b5p-3,
    0x1.8d7632efaa944p-3, 0x1.9d252d0cec312p-3, 0x1.accdb297a0765p-3,
    0x1.bc6f84edc6199p-3, 0x1.cc0a6588289a3p-3, 0x1.db9e15fb5a5d0p-3,
    0x1.eb2a57f8ae5a3p-3, 0x1.faaeed4f31577p-3, 0x1.0515cbf65155cp-2,
    0x1.0cd00cef36436p-2, 0x1.14861aa94ddebp-2, 0x1.1c37d64c6b876p-2,
    0x1.23e52111aaf36p-2, 0x1.2b8ddc43eb49fp-2, 0x1.3331e94049f87p-2,
    0x1.3ad129769d3d8p-2, 0x1.426b7e69ee697p-2, 0x1.4a00c9b0f3d20p-2,
    0x1.5190ecf68a77ap-2, 0x1.591bc9fa2f597p-2, 0x1.60a1429078775p-2,
    0x1.682138a38d7f7p-2, 0x1.6f9b8e33a0255p-2, 0x1.7710255764214p-2,
    0x1.7e7ee03c86d4ep-2, 0x1.85e7a12826949p-2, 0x1.8d4a4a774992fp-2,
    0x1.94a6be9f546c5p-2, 0x1.9bfce02e80510p-2, 0x1.a34c91cc50ccap-2,
    0x1.aa95b63a09277p-2, 0x1.b1d8305321617p-2, 0x1.b913e30dbac43p-2,
    0x1.c048b17b140a3p-2, 0x1.c7767ec7fd19ep-2, 0x1.ce9d2e3d4a51fp-2,
    0x1.d5bca34047661p-2, 0x1.dcd4c15329c9ap-2, 0x1.e3e56c1582a69p-2,
    0x1.eaee8744b05f0p-2, 0x1.f1eff6bc4f97bp-2, 0x1.f8e99e76abc97p-2,
    0x1.ffdb628d2f57ap-2, 0x1.0362939c69955p-1, 0x1.06d3686946e5bp-1,
    0x1.0a4021e9e1001p-1, 0x1.0da8b26b5672ep-1, 0x1.110d0c4b69c3bp-1,
    0x1.146d21f8b7f82p-1, 0x1.17c8e5f2eedb0p-1, 0x1.1b204acb02fddp-1,
    0x1.1e7343236574cp-1, 0x1.21c1c1b0394cfp-1, 0x1.250bb93788bbbp-1,
    0x1.28511c917a067p-1, 0x1.2b91dea88421ep-1, 0x1.2ecdf279a3082p-1,
    0x1.32054b148bc4fp-1, 0x1.3537db9be0367p-1, 0x1.386597456282bp-1,
    0x1.3b8e715a2840ap-1, 0x1.3eb25d36cd53ap-1, 0x1.41d14e4ba6790p-1,
    0x1.44eb381cf386bp-1, 0x1.48000e431159fp-1, 0x1.4b0fc46aab761p-1,
    0x1.4e1a4e54ed51bp-1, 0x1.511f9fd7b351cp-1, 0x1.541facddbb724p-1,
    0x1.571a6966d59b3p-1, 0x1.5a0fc98813a12p-1, 0x1.5cffc16bf8f0dp-1,
    0x1.5fea4552a9e57p-1, 0x1.62cf49921ac79p-1, 0x1.65aec2963e755p-1,
    0x1.6888a4e134b2fp-1, 0x1.6b5ce50b7821ap-1,
};
static const double chaplygin_dm_TRIG_S_LO[86] = {
    -0x1.afcb2bcc6f03bp-59, 0x1.d8468724f0f9ep-57, -0x1.6ef95099769a5p-57,
    -0x1.e4d0f05dee058p-57, 0x1.47d666b66cb91p-57, 0x1.949db2ac072fcp-58,
    -0x1.6f443063f89b6p-57, -0x1.32c5c8b81c919p-66, 0x1.5ab50e23c97c3p-59,
    -0x1.20fa262cbb953p-57, 0x1.9c43d80b1137dp-58, -0x1.9883b57d6cdeap-58,
    0x1.9c1a56a7b0cabp-57, -0x1.868d09bc87c6bp-57, -0x1.32e20d6cc6fc2p-57,
    -0x1.0be06af572cebp-57, -0x1.15d88508e32b8p-57, -0x1.9b8c29dfd8ec7p-56,
    -0x1.9fb0a0c93e2b4p-56, -0x1.be881b5b615a4p-57, 0x1.46076fe0dcff4p-56,
    -0x1.4f080334eff18p-56, 0x1.1553899f2d807p-57, 0x1.e0cb6b40c302cp-56,
    0x1.03d550487839ap-63, -0x1.f09c75705c59fp-56, 0x1.823ba6bb08eadp-56,
    0x1.b357155eef0f3p-56, 0x1.7c74bac3fe0cbp-57, 0x1.b1fd80ba89133p-58,
    -0x1.d889202444aadp-56, 0x1.42bc14ee9da0dp-56, -0x1.6ead7314bb6cep-57,
    -0x1.b63bcdabf5af2p-56, 0x1.8a40e9b5face0p-56, 0x1.44a02ea766326p-56,
    -0x1.69ce13e683f58p-56, 0x1.09e39a320b0a4p-56, -0x1.a310e3b50cecdp-58,
    -0x1.6293eb13c0381p-57, -0x1.ae242cb99f519p-56, -0x1.e38ad2f6c3ff1p-56,
    0x1.19fe6757e9fa7p-57, -0x1.eb14d1a3d5826p-58, -0x1.2fc8a12dae298p-57,
    0x1.28a44a75fc29cp-56, 0x1.0d4c6e171fd9ap-56, -0x1.0a4821099f88fp-58,
    -0x1.789b43c9b027dp-58, 0x1.17212f8a7525cp-56, 0x1.9d950af2d00a3p-58,
    0x1.f4a992e905b6ap-57, -0x1.2d8cd78397b01p-55, 0x1.3f5ae4538ff1bp-55,
    -0x1.6f643a13914f6p-55, -0x1.a58def0bee909p-55, 0x1.d918998809981p-55,
    0x1.bf9535e2739a8p-56, 0x1.35e57102e2488p-57, -0x1.f190c70cbb5fep-58,
    0x1.22a3fa4f41d5ap-56, 0x1.e5b324b23aa31p-58, 0x1.ea3d02457bccep-56,
    -0x1.01df1d9a16b70p-55, -0x1.fa371db216ab0p-55, 0x1.d3557e0e7e37ep-55,
    0x1.f6b42095a135bp-55, 0x1.b327e7af040f0p-57, -0x1.10fada93b07a8p-56,
    -0x1.97653a7d2f07ap-56, -0x1.be570e1570fc0p-58, 0x1.4608fd287ecf5p-55,
    -0x1.3ed6c1e6a5505p-55, -0x1.b194a7463ed10p-55, 0x1.0da05738cc59cp-61,
    -0x1.a492f89b7c76ap-55, -0x1.5c0e861c48831p-55, 0x1.232c28520d391p-56,
    0x1.c843b4d0fb197p-58, -0x1.d82e2b7d4227bp-55, 0x1.96cb370eb578ap-55,
    0x1.0b6cef7ee20b7p-55, -0x1.edd9855b6241ap-55, 0x1.126f96b71053cp-55,
    -0x1.6b7d37644d5e6p-55, -0x1.5d5158f702e0fp-57,
};
static const double chaplygin_dm_TRIG_C_HI[86] = {
    0x1.fc015527d5bd3p-1, 0x1.fb7db2bfe0695p-1, 0x1.faf22263c4bd3p-1,
    0x1.fa5ea641c36f2p-1, 0x1.f9c340a7cc428p-1, 0x1.f91ff40374d01p-1,
    0x1.f874c2e1eecf6p-1, 0x1.f7c1afeffde24p-1, 0x1.f706bdf9ece1cp-1,
    0x1.f643efeb82acdp-1, 0x1.f57948cff6797p-1, 0x1.f4a6cbd1e3a79p-1,
    0x1.f3cc7c3b3d16ep-1, 0x1.f2ea5d753ffedp-1, 0x1.f20073086649fp-1,
    0x1.f10ec09c5873bp-1, 0x1.f01549f7deea1p-1, 0x1.ef141300d2f26p-1,
    0x1.ee0b1fbc0f11cp-1, 0x1.ecfa744d5efa1p-1, 0x1.ebe214f76efa8p-1,
    0x1.eac2061bbaf4fp-1, 0x1.e99a4c3a7cd83p-1, 0x1.e86aebf29a9edp-1,
    0x1.e733ea0193d40p-1, 0x1.e5f54b436e9d0p-1, 0x1.e4af14b2a449cp-1,
    0x1.e3614b680d6a5p-1, 0x1.e20bf49acd6c1p-1, 0x1.e0af15a03dbcep-1,
    0x1.df4ab3ebd875ep-1, 0x1.ddded50f228d6p-1, 0x1.dc6b7eb995912p-1,
    0x1.daf0b6b888e83p-1, 0x1.d96e82f71a9dcp-1, 0x1.d7e4e97e17b4ap-1,
    0x1.d653f073e4040p-1, 0x1.d4bb9e1c619e0p-1, 0x1.d31bf8d8d7c06p-1,
    0x1.d1750727d94f0p-1, 0x1.cfc6cfa52ad9fp-1, 0x1.ce115909a82e5p-1,
    0x1.cc54aa2b2972ep-1, 0x1.ca90c9fc67d0bp-1, 0x1.c8c5bf8ce1a84p-1,
    0x1.c6f39208be53bp-1, 0x1.c51a48b8b175ep-1, 0x1.c339eb01ddd81p-1,
    0x1.c1528065b7d50p-1, 0x1.bf641081e7536p-1, 0x1.bd6ea310294f5p-1,
    0x1.bb723fe630f32p-1, 0x1.b96eeef58840ep-1, 0x1.b764b84b704c2p-1,
    0x1.b553a410c104ep-1, 0x1.b33bba89c8948p-1, 0x1.b11d04162a4c6p-1,
    0x1.aef78930bd275p-1, 0x1.accb526f69de5p-1, 0x1.aa98688308913p-1,
    0x1.a85ed4373e02dp-1, 0x1.a61e9e72586afp-1, 0x1.a3d7d0352bdcfp-1,
    0x1.a18a729aee445p-1, 0x1.9f368ed912f85p-1, 0x1.9cdc2e3f25e5cp-1,
    0x1.9a7b5a36a6514p-1, 0x1.98141c42e1310p-1, 0x1.95a67e00cb1fdp-1,
    0x1.93328926d9e92p-1, 0x1.90b84784ddaf7p-1, 0x1.8e37c303d9ad1p-1,
    0x1.8bb105a5dc900p-1, 0x1.89241985d871fp-1, 0x1.869108d77a6c6p-1,
    0x1.83f7dde701ca0p-1, 0x1.8158a31916d5dp-1, 0x1.7eb362eaa1488p-1,
    0x1.7c0827f09e54fp-1, 0x1.7956fcd7f6543p-1, 0x1.769fec655211fp-1,
    0x1.73e30174efba1p-1, 0x1.712046fa77678p-1, 0x1.6e57c800cf55ep-1,
    0x1.6b898fa9efb5dp-1, 0x1.68b5a92eb6253p-1,
};
static const double chaplygin_dm_TRIG_C_LO[86] = {
    0x1.b68f35094efb8p-55, 0x1.21dadf4f65ab1p-55, -0x1.52ace133a2769p-58,
    0x1.04da6ed17cc7cp-59, 0x1.c5b6b063b7462p-55, -0x1.7d03f4d3a9e4cp-57,
    -0x1.c6514e1332b16p-55, -0x1.8f55bc47540b1p-56, -0x1.698c80c36dcb4p-55,
    0x1.6b00ac1fe28acp-56, 0x1.e3a0d3e03b1d4p-57, 0x1.13df0edaebb57p-55,
    -0x1.21a3ad28a3494p-57, 0x1.cc4215f56d583p-55, 0x1.b940416c1984bp-56,
    0x1.d9072762c1283p-55, 0x1.d3c1e99e5cafdp-55, -0x1.2aa1b08ded372p-55,
    -0x1.bfd2380bbc3b1p-59, -0x1.56d0a4af541d0p-58, -0x1.02f9f12ba543ep-55,
    0x1.2c1d53e94658dp-57, -0x1.2264b1bc53ce8p-55, 0x1.9397afdbb58a7p-55,
    -0x1.6428b3546ce13p-55, 0x1.7eb0fd02fc8bcp-55, -0x1.68ca02e8a6833p-55,
    -0x1.27793aa015237p-56, -0x1.660aec7ef636bp-58, 0x1.fe8e702771ae6p-58,
    -0x1.e2d8a7e6736c4p-55, -0x1.e80c8d42ba2bfp-57, 0x1.4b364776dcd35p-58,
    0x1.a249e2b5e5ceap-55, 0x1.ff61bd5d2039dp-55, -0x1.3b770352bed94p-57,
    -0x1.76236434bec37p-55, 0x1.f34bb77858f61p-55, 0x1.e60dd3089cbddp-56,
    0x1.0d52b1ec1a48ep-55, 0x1.8b5b5508f2a0dp-55, 0x1.1f139bb31109ap-55,
    0x1.4ee162ba83a98p-57, -0x1.46a81485e3462p-57, 0x1.ab3d1a1590123p-56,
    -0x1.741dbfbaadb42p-55, -0x1.1bbb43b9aa880p-57, -0x1.caaf5ee82c5c0p-55,
    -0x1.892111312e828p-55, 0x1.b7bd71628a9a1p-55, 0x1.31bbcc88c109dp-56,
    0x1.72bd2452d0a39p-56, 0x1.45a3cc78fade0p-58, -0x1.f5848c21b389bp-55,
    0x1.8ff7947027a15p-58, 0x1.ea6a51d1f6ca9p-55, 0x1.1dd561efbc0c2p-56,
    -0x1.f836279746f94p-56, 0x1.8fb6a8dd6b6ccp-55, -0x1.b83d607cd5072p-63,
    0x1.9be06385ec792p-57, 0x1.58330e2fd453fp-55, -0x1.68dbaeca19669p-55,
    0x1.95e25736c0357p-60, -0x1.1d200c5791606p-55, 0x1.3f99112993f62p-55,
    0x1.722cfcc9fa7a9p-55, 0x1.d1ff80488f08dp-55, -0x1.0befda21f862dp-55,
    -0x1.bb77003600cdap-55, -0x1.0feb10ab93b87p-56, -0x1.463a4b53d4bf8p-57,
    0x1.863e03e9474c1p-55, 0x1.c48d9c413ed84p-55, 0x1.338ffe2bfe9ddp-56,
    -0x1.152cf609bc6e8p-59, -0x1.de8b90b8228dep-57, 0x1.a1d65a4a5959fp-58,
    -0x1.c73d6d72aee68p-57, -0x1.ab276e9d45ae4p-55, -0x1.827d5cf8c68c5p-57,
    -0x1.5d3ae3d94ad5fp-57, 0x1.425b0a5029c81p-55, 0x1.60286dedbd0a6p-55,
    0x1.15ac786ccf4b2p-56, -0x1.9a91ad985f89cp-55,
};
static const double chaplygin_dm_ATAN_POLY[4] = {
    -0x1.5555555555555p-2, 0x1.999999999999ap-3, -0x1.2492492492492p-3,
    0x1.c71c71c71c71cp-4,
};
static const double chaplygin_dm_ATAN_HI[65] = {
    0x0.0p+0, 0x1.fff555bbb729bp-7, 0x1.ffd55bba97625p-6,
    0x1.7fb818430da2ap-5, 0x1.ff55bb72cfdeap-5, 0x1.3f59f0e7c559dp-4,
    0x1.7ee182602f10fp-4, 0x1.be39ebe6f07c3p-4, 0x1.fd5ba9aac2f6ep-4,
    0x1.1e1fafb043727p-3, 0x1.3d6eee8c6626cp-3, 0x1.5c9811e3ec26ap-3,
    0x1.7b97b4bce5b02p-3, 0x1.9a6a8e96c8626p-3, 0x1.b90d7529260a2p-3,
    0x1.d77d5df205736p-3, 0x1.f5b75f92c80ddp-3, 0x1.09dc597d86362p-2,
    0x1.18bf5a30bf178p-2, 0x1.278372057ef46p-2, 0x1.362773707ebccp-2,
    0x1.44aa436c2af0ap-2, 0x1.530ad9951cd4ap-2, 0x1.614840309cfe2p-2,
    0x1.6f61941e4def1p-2, 0x1.7d5604b63b3f7p-2, 0x1.8b24d394a1b25p-2,
    0x1.98cd5454d6b18p-2, 0x1.a64eec3cc23fdp-2, 0x1.b3a911da65c6cp-2,
    0x1.c0db4c94ec9f0p-2, 0x1.cde53432c1351p-2, 0x1.dac670561bb4fp-2,
    0x1.e77eb7f175a34p-2, 0x1.f40dd0b541418p-2, 0x1.0039c73c1a40cp-1,
    0x1.0657e94db30d0p-1, 0x1.0c6145b5b43dap-1, 0x1.1255d9bfbd2a9p-1,
    0x1.1835a88be7c13p-1, 0x1.1e00babdefeb4p-1, 0x1.23b71e2cc9e6ap-1,
    0x1.2958e59308e31p-1, 0x1.2ee628406cbcap-1, 0x1.345f01cce37bbp-1,
    0x1.39c391cd4171ap-1, 0x1.3f13fb89e96f4p-1, 0x1.445065b795b56p-1,
    0x1.4978fa3269ee1p-1, 0x1.4e8de5bb6ec04p-1, 0x1.538f57b89061fp-1,
    0x1.587d81f732fbbp-1, 0x1.5d58987169b18p-1, 0x1.6220d115d7b8ep-1,
    0x1.66d663923e087p-1, 0x1.6b798920b3d99p-1, 0x1.700a7c5784634p-1,
    0x1.748978fba8e0fp-1, 0x1.78f6bbd5d315ep-1, 0x1.7d528289fa093p-1,
    0x1.819d0b7158a4dp-1, 0x1.85d69576cc2c5p-1, 0x1.89ff5ff57f1f8p-1,
    0x1.8e17aa99cc05ep-1, 0x1.921fb54442d18p-1,
};
static const double chaplygin_dm_ATAN_LO[65] = {
    0x0.0p+0, -0x1.220c39d4dff50p-61, -0x1.5ec431444912cp-60,
    -0x1.86ef8f794f105p-63, -0x1.c934d86d23f1dp-60, 0x1.ac4ce285df847p-58,
    -0x1.cfb654c0c3d98p-58, 0x1.f7b8f29a05987p-58, -0x1.cd37686760c17p-59,
    -0x1.b485914dacf8cp-59, 0x1.61a3b0ce9281bp-57, -0x1.054ab2c010f3dp-58,
    0x1.347b0b4f881cap-58, 0x1.cf601e7b4348ep-59, 0x1.17b10d2e0e5abp-61,
    0x1.c648d1534597ep-57, 0x1.8ab6e3cf7afbdp-57, 0x1.62e47390cb865p-56,
    0x1.30ca4748b1bf9p-57, -0x1.077cdd36dfc81p-56, -0x1.963a544b672d8p-57,
    -0x1.5d5e43c55b3bap-56, -0x1.2566480884082p-57, -0x1.a725715711f00p-56,
    -0x1.c63aae6f6e918p-56, 0x1.69c885c2b249ap-56, 0x1.b6d0ba3748fa8p-56,
    0x1.9e6c988fd0a77p-56, -0x1.24dec1b50b7ffp-56, 0x1.ae187b1ca5040p-56,
    -0x1.cc1ce70934c34p-56, -0x1.a2cfa4418f1adp-56, 0x1.a2b7f222f65e2p-56,
    0x1.0e53dc1bf3435p-56, -0x1.a3992dc382a23p-57, -0x1.b32c949c9d593p-55,
    -0x1.d5b495f6349e6p-56, 0x1.974fa13b5404fp-58, -0x1.2bdaee1c0ee35p-58,
    0x1.c621cec00c301p-55, -0x1.928df287a668fp-58, 0x1.c421c9f38224ep-57,
    -0x1.09e73b0c6c087p-56, 0x1.c5d5e9ff0cf8dp-55, 0x1.1021137c71102p-55,
    -0x1.2304331d8bf46p-55, 0x1.ecf8b492644f0p-56, -0x1.f76d0163f79c8p-56,
    0x1.2419a87f2a458p-56, 0x1.4a33dbeb3796cp-55, -0x1.1bb74abda520cp-55,
    -0x1.5e5c9d8c5a950p-56, 0x1.0028e4bc5e7cap-57, -0x1.2b785350ee8c1p-57,
    -0x1.6ea6febe8bbbap-56, -0x1.a80386188c50ep-55, -0x1.8c34d25aadef6p-56,
    0x1.7b2a6165884a1p-59, 0x1.406a089803740p-55, 0x1.560821e2f3aa9p-55,
    -0x1.bf76229d3b917p-56, 0x1.6b66e7fc8b8c3p-57, -0x1.55b9a5e177a1bp-55,
    -0x1.ec182ab042f61p-56, 0x1.1a62633145c07p-55,
};
static const double chaplygin_dm_SINH_POLY[6] = {
    0x1.5555555555555p-3, 0x1.1111111111111p-7, 0x1.a01a01a01a01ap-13,
    0x1.71de3a556c734p-19, 0x1.ae64567f544e4p-26, 0x1.6124613a86d09p-33,
};
static const double chaplygin_dm_CBRT_POLY[6] = {
    0x1.4c7608a04eba1p-8, -0x1.8bd2dce403128p-5, 0x1.92bfc00e33108p-3,
    -0x1.d758498b983bcp-2, 0x1.a9da3cc66f245p-1, 0x1.e68ceb1fc3429p-2,
};
static const double chaplygin_dm_CBRT_2J[3] = {
    0x1.0000000000000p+0, 0x1.428a2f98d728bp+0, 0x1.965fea53d6e3dp+0,
};
static const uint64_t chaplygin_dm_TWO_OVER_PI_BITS[20] = {
    UINT64_C(0x0000000000000000), UINT64_C(0xa2f9836e4e441529),
    UINT64_C(0xfc2757d1f534ddc0), UINT64_C(0xdb6295993c439041),
    UINT64_C(0xfe5163abdebbc561), UINT64_C(0xb7246e3a424dd2e0),
    UINT64_C(0x06492eea09d1921c), UINT64_C(0xfe1deb1cb129a73e),
    UINT64_C(0xe88235f52ebb4484), UINT64_C(0xe99c7026b45f7e41),
    UINT64_C(0x3991d639835339f4), UINT64_C(0x9c845f8bbdf9283b),
    UINT64_C(0x1ff897ffde05980f), UINT64_C(0xef2f118b5a0a6d1f),
    UINT64_C(0x6d367ecf27cb09b7), UINT64_C(0x4f463f669e5fea2d),
    UINT64_C(0x7527bac7ebe5f17b), UINT64_C(0x3d0739f78a5292ea),
    UINT64_C(0x6bfb5fb11f8d5d08), UINT64_C(0x56033046fc7b6bab),
};
/* ---- END GENERATED CONSTANTS ---- */
/* ------------------------------------------------------------------------------------------ helpers */

#define CHAPLYGIN_DM_SHIFT 0x1.8p52 /* (z + SHIFT) - SHIFT rounds |z| < 2^51 to an integer */

static inline uint64_t chaplygin_dm__bits(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static inline double chaplygin_dm__double(uint64_t u)
{
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

/* 2^k for -1022 <= k <= 1023 (exact). */
static inline double chaplygin_dm__pow2(int k)
{
    return chaplygin_dm__double((uint64_t)(k + 1023) << 52);
}

/* The one NaN every function returns (positive quiet NaN; inputs' payloads are not kept). */
static inline double chaplygin_dm__nan(void)
{
    return chaplygin_dm__double(UINT64_C(0x7ff8000000000000));
}

static inline double chaplygin_dm__inf(void)
{
    return chaplygin_dm__double(UINT64_C(0x7ff0000000000000));
}

/* s + e = a + b exactly, when a == 0 or exponent(a) >= exponent(b) (Dekker's Fast2Sum). */
static inline double chaplygin_dm__fast_two_sum(double a, double b, double *e)
{
    double s = a + b;
    *e = b - (s - a);
    return s;
}

/* s + e = a + b exactly, any order of magnitude (Knuth's 2Sum). */
static inline double chaplygin_dm__two_sum(double a, double b, double *e)
{
    double s = a + b;
    double bb = s - a;
    *e = (a - (s - bb)) + (b - bb);
    return s;
}

/* p + e = a * b exactly (Dekker's product with Veltkamp's splitting, no FMA), for |a|, |b| <
 * 2^995 and no underflow in the partial products. */
static inline double chaplygin_dm__two_prod(double a, double b, double *e)
{
    double p = a * b;
    double ca = 134217729.0 * a; /* 2^27 + 1 */
    double ah = ca - (ca - a);
    double al = a - ah;
    double cb = 134217729.0 * b;
    double bh = cb - (cb - b);
    double bl = b - bh;
    *e = (((ah * bh - p) + ah * bl) + al * bh) + al * bl;
    return p;
}

/* RN((h + l) 2^k) for a normalised pair (|l| <= ulp(h)/2) with 1/2 <= h + l < 4 and
 * -1100 < k < 1100: one rounding, also when the result is subnormal (rounded once to the
 * subnormal grid) or overflows. */
static inline double chaplygin_dm__scale(double h, double l, int k)
{
    double v = h + l;
    if (k > 1000)
        return (v * chaplygin_dm__pow2(k - 100)) * 0x1p100;
    if (k >= -1021)
        return v * chaplygin_dm__pow2(k);
    {
        double G = chaplygin_dm__pow2(-1022 - k); /* the result is subnormal iff v < G */
        double d, f, S, g;
        if (v >= G)
            return (v * chaplygin_dm__pow2(k + 200)) * 0x1p-200;
        d = (h + G) - G; /* h rounded to the grid G 2^-52 (= 2^-1074 after scaling) */
        f = (h - d) + l;
        S = 1.5 * G;
        g = (f + S) - S; /* the rest rounded to the grid: -grid, 0 or +grid */
        return ((d + g) * chaplygin_dm__pow2(k + 200)) * 0x1p-200;
    }
}

/* ---------------------------------------------------------------------------------------- exp */

/* e^(xh + xl) = 2^m (h + l), (h, l) a normalised pair with 0.99 < h + l < 2.01, for |xh| <= 746
 * and |xl| <= 2^-40.  x = k ln2/128 + r, |r| <= ln2/256; 2^(j/128) from the table; Taylor
 * polynomial of degree 6 for e^r - 1. */
static inline double chaplygin_dm__exp_kernel(double xh, double xl, double *l, int *m)
{
    double z = xh * chaplygin_dm_EXP_INV_LN2_N;
    double kd = (z + CHAPLYGIN_DM_SHIFT) - CHAPLYGIN_DM_SHIFT;
    int64_t k = (int64_t)kd;
    int j = (int)((uint64_t)k & 127u);
    double t = xh - kd * chaplygin_dm_EXP_LN2_N_HI; /* exact */
    double r = t + (xl - kd * chaplygin_dm_EXP_LN2_N_LO);
    double r2 = r * r;
    const double *c = chaplygin_dm_EXP_POLY;
    double q = (c[0] + r * c[1]) + r2 * ((c[2] + r * c[3]) + r2 * c[4]);
    double p = r + r2 * q; /* e^r - 1 */
    double th = chaplygin_dm_EXP_T_HI[j];
    double small = chaplygin_dm_EXP_T_LO[j] + th * p;
    *m = (int)((k - j) / 128);
    return chaplygin_dm__fast_two_sum(th, small, l);
}

/* e^x, faithful (design bound below), subnormal results rounded once. */
static inline double chaplygin_exp(double x)
{
    double h, l;
    int m;
    if (!(x <= 709.8)) /* overflow, +inf or NaN */
        return x != x ? chaplygin_dm__nan() : chaplygin_dm__inf();
    if (x < -746.0) /* e^x < 2^-1076: rounds to +0 (also -inf) */
        return 0.0;
    h = chaplygin_dm__exp_kernel(x, 0.0, &l, &m);
    return chaplygin_dm__scale(h, l, m);
}

/* ---------------------------------------------------------------------------------------- log */

/* x > 0 finite: x = 2^e m with m in [sqrt2/2, sqrt2), j = round(256 (m - 1)) in [-75, 106],
 * u = m r_j - 1 = uh + *ul exactly (r_j has at most 11 significant bits). Returns j + 75. */
static inline int chaplygin_dm__log_reduce(double x, int *e, double *uh, double *ul)
{
    uint64_t ix = chaplygin_dm__bits(x), top, mb;
    double m, r, mh, ml, t1, t2;
    int idx, adj = 0, below, sh;
    if (ix < UINT64_C(0x0010000000000000)) { /* subnormal */
        ix = chaplygin_dm__bits(x * 0x1p54);
        adj = -54;
    }
    /* e = floor(log2(x / (sqrt2/2))), m = x 2^-e, without a branch */
    top = (ix + ((UINT64_C(1024) << 52) - chaplygin_dm__bits(0.5 * chaplygin_dm_LOG_SQRT2))) >> 52;
    *e = (int)top - 1024 + adj;
    mb = ix - (top << 52) + (UINT64_C(1024) << 52); /* the bits of m */
    m = chaplygin_dm__double(mb);
    /* j = 256 (m - 1) rounded half up, from the 52 fraction bits f: round(f 2^-44) for m >= 1,
     * round(f 2^-45) - 128 for m < 1 (m = (1 + f 2^-52) / 2) */
    below = (int)(1023 - (mb >> 52));
    sh = 44 + below;
    idx = (int)(((mb & UINT64_C(0x000fffffffffffff)) + (UINT64_C(1) << (sh - 1))) >> sh) -
          128 * below + 75;
    r = chaplygin_dm_LOG_R[idx];
    mh = chaplygin_dm__double(mb & ~UINT64_C(0x7ff)); /* 42 significant bits */
    ml = m - mh;
    t1 = mh * r - 1.0; /* mh r exact (53 bits), - 1 exact (Sterbenz) */
    t2 = ml * r;       /* exact */
    *uh = chaplygin_dm__fast_two_sum(t1, t2, ul);
    return idx;
}

/* Special values of log, log2, log10; 0 when x is positive and finite. */
static inline int chaplygin_dm__log_special(double x, double *result)
{
    uint64_t ix = chaplygin_dm__bits(x);
    if (ix - 1u < UINT64_C(0x7fefffffffffffff)) /* 0 < x < inf */
        return 0;
    if (x == 0.0)
        *result = -chaplygin_dm__inf();
    else if (ix == UINT64_C(0x7ff0000000000000))
        *result = x;
    else /* x < 0 or NaN */
        *result = chaplygin_dm__nan();
    return 1;
}

/* log x = H + lo + log1p(u), H = e ln2_hi + log(1/r_j)_hi exact (multiples of 2^-42). */
static inline double chaplygin_log(double x)
{
    double uh, ul, H, lo, s, es, u2, q, res;
    const double *c = chaplygin_dm_LOG_POLY;
    int e, idx;
    if (chaplygin_dm__log_special(x, &res))
        return res;
    idx = chaplygin_dm__log_reduce(x, &e, &uh, &ul);
    H = (double)e * chaplygin_dm_LN2_HI + chaplygin_dm_LOG_L_HI[idx];
    lo = (double)e * chaplygin_dm_LN2_LO + chaplygin_dm_LOG_L_LO[idx];
    s = chaplygin_dm__fast_two_sum(H, uh, &es);
    u2 = uh * uh;
    q = ((c[0] + uh * c[1]) + u2 * (c[2] + uh * c[3])) + (u2 * u2) * (c[4] + uh * c[5]);
    return s + (es + (ul + (lo + u2 * q)));
}

/* log_b x = e log_b(2) + log_b(1/r_j) + log1p(u) / ln b: the reduction of log, u / ln b as an
 * exact product plus the low parts. */
static inline double chaplygin_dm__log_base(double x, double eh, double el, const double *lh,
                                            const double *ll, double kh, double kl,
                                            const double *c)
{
    double uh, ul, H, lo, p, pe, s, es, u2, q, res;
    int e, idx;
    if (chaplygin_dm__log_special(x, &res))
        return res;
    idx = chaplygin_dm__log_reduce(x, &e, &uh, &ul);
    H = (double)e * eh + lh[idx]; /* exact */
    lo = (double)e * el + ll[idx];
    p = chaplygin_dm__two_prod(uh, kh, &pe);
    s = chaplygin_dm__fast_two_sum(H, p, &es);
    u2 = uh * uh;
    q = ((c[0] + uh * c[1]) + u2 * (c[2] + uh * c[3])) + (u2 * u2) * (c[4] + uh * c[5]);
    return s + (es + ((pe + (uh * kl + ul * kh)) + (lo + u2 * q)));
}

static inline double chaplygin_log2(double x)
{
    return chaplygin_dm__log_base(x, chaplygin_dm_LOG2_E_HI, chaplygin_dm_LOG2_E_LO,
                                  chaplygin_dm_LOG2_L_HI, chaplygin_dm_LOG2_L_LO,
                                  chaplygin_dm_LOG2_K_HI, chaplygin_dm_LOG2_K_LO,
                                  chaplygin_dm_LOG2_POLY);
}

static inline double chaplygin_log10(double x)
{
    return chaplygin_dm__log_base(x, chaplygin_dm_LOG10_E_HI, chaplygin_dm_LOG10_E_LO,
                                  chaplygin_dm_LOG10_L_HI, chaplygin_dm_LOG10_L_LO,
                                  chaplygin_dm_LOG10_K_HI, chaplygin_dm_LOG10_K_LO,
                                  chaplygin_dm_LOG10_POLY);
}

/* log x = h + *l with relative error below 2^-68 (x > 0 finite), for pow: -u^2/2 exact. */
static inline double chaplygin_dm__log_dd(double x, double *l)
{
    double uh, ul, H, lo, s1, e1, q, qe, s2, e2, R, tail;
    const double *c = chaplygin_dm_LOGDD_POLY;
    int e, idx;
    idx = chaplygin_dm__log_reduce(x, &e, &uh, &ul);
    H = (double)e * chaplygin_dm_LN2_HI + chaplygin_dm_LOG_L_HI[idx];
    lo = (double)e * chaplygin_dm_LN2_LO + chaplygin_dm_LOG_L_LO[idx];
    s1 = chaplygin_dm__fast_two_sum(H, uh, &e1);
    q = chaplygin_dm__two_prod(uh, uh, &qe);
    s2 = chaplygin_dm__fast_two_sum(s1, -0.5 * q, &e2);
    R = ((c[0] + uh * c[1]) + q * (c[2] + uh * c[3])) + (q * q) * (c[4] + uh * c[5]);
    tail = ((e1 + e2) + (ul - 0.5 * qe)) + ((lo - uh * ul) + (uh * q) * R);
    return chaplygin_dm__fast_two_sum(s2, tail, l);
}

/* ---------------------------------------------------------------------------------------- pow */

/* 0: y not an integer, 1: odd integer, 2: even integer (|y| >= 2^53 and infinities count as even). */
static inline int chaplygin_dm__integer_kind(double y)
{
    double ay = fabs(y);
    int64_t k;
    if (!(ay < 0x1p53))
        return 2;
    k = (int64_t)ay; /* truncation */
    if ((double)k != ay)
        return 0;
    return (k & 1) ? 1 : 2;
}

/* |x|^y = e^(y log|x|) for finite ax = |x| > 0 and |y| < 2^64, log|x| as a double-double. */
static inline double chaplygin_dm__pow_abs(double ax, double y)
{
    double lh, ll, ph, pe, pl, h, l;
    int m;
    lh = chaplygin_dm__log_dd(ax, &ll);
    ph = chaplygin_dm__two_prod(y, lh, &pe);
    pl = pe + y * ll;
    if (ph > 709.8)
        return chaplygin_dm__inf();
    if (ph < -746.0)
        return 0.0;
    h = chaplygin_dm__exp_kernel(ph, pl, &l, &m);
    return chaplygin_dm__scale(h, l, m);
}

/* x^y with the special cases of C99 Annex F. */
static inline double chaplygin_pow(double x, double y)
{
    double ax = fabs(x), res;
    int kind, negative;
    if (chaplygin_dm__bits(x) - 1u < UINT64_C(0x7fefffffffffffff) && fabs(y) < 0x1p64)
        return chaplygin_dm__pow_abs(x, y); /* 0 < x < inf (y = 0 and x = 1 give 1 exactly) */
    if (y == 0.0 || x == 1.0)
        return 1.0;
    if (x != x || y != y)
        return chaplygin_dm__nan();
    kind = chaplygin_dm__integer_kind(y);
    negative = (chaplygin_dm__bits(x) >> 63) && kind == 1;
    if (x == 0.0) {
        if (y < 0.0)
            return negative ? -chaplygin_dm__inf() : chaplygin_dm__inf();
        return negative ? -0.0 : 0.0;
    }
    if (fabs(y) == chaplygin_dm__inf()) {
        if (ax == 1.0)
            return 1.0; /* x == -1 */
        return (ax < 1.0) == (y < 0.0) ? chaplygin_dm__inf() : 0.0;
    }
    if (ax == chaplygin_dm__inf()) {
        if (y < 0.0)
            return negative ? -0.0 : 0.0;
        return negative ? -chaplygin_dm__inf() : chaplygin_dm__inf();
    }
    if (x < 0.0 && kind == 0)
        return chaplygin_dm__nan();
    if (!(fabs(y) < 0x1p64)) { /* |y log|x|| >= 2^11: overflow or underflow (x != +-1 here) */
        if (ax == 1.0)
            return 1.0;
        return (ax > 1.0) == (y > 0.0) ? chaplygin_dm__inf() : 0.0; /* y even: positive */
    }
    res = chaplygin_dm__pow_abs(ax, y);
    return negative ? -res : res;
}

/* ------------------------------------------------------------------------------------ sin, cos */

/* mul64: hi * 2^64 + lo = a * b. */
static inline uint64_t chaplygin_dm__mul64(uint64_t a, uint64_t b, uint64_t *hi)
{
#if defined(__SIZEOF_INT128__) && !defined(CHAPLYGIN_DETMATH_NO_INT128)
    __extension__ typedef unsigned __int128 u128; /* __extension__: no -pedantic warning */
    u128 p = (u128)a * b;
    *hi = (uint64_t)(p >> 64);
    return (uint64_t)p;
#else
    uint64_t a0 = a & 0xffffffffu, a1 = a >> 32, b0 = b & 0xffffffffu, b1 = b >> 32;
    uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    uint64_t mid = (p00 >> 32) + (p01 & 0xffffffffu) + (p10 & 0xffffffffu);
    *hi = p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
    return (mid << 32) | (p00 & 0xffffffffu);
#endif
}

/* Number of leading zero bits of x != 0 (binary search; the same steps in the numpy port). */
static inline int chaplygin_dm__clz64(uint64_t x)
{
    int n = 0;
    if (x < (UINT64_C(1) << 32)) { n += 32; x <<= 32; }
    if (x < (UINT64_C(1) << 48)) { n += 16; x <<= 16; }
    if (x < (UINT64_C(1) << 56)) { n += 8; x <<= 8; }
    if (x < (UINT64_C(1) << 60)) { n += 4; x <<= 4; }
    if (x < (UINT64_C(1) << 62)) { n += 2; x <<= 2; }
    if (x < (UINT64_C(1) << 63)) { n += 1; }
    return n;
}

/* (x << s) | (y >> (64 - s)) for 0 <= s < 64. */
static inline uint64_t chaplygin_dm__shl2(uint64_t x, uint64_t y, int s)
{
    return s == 0 ? x : (x << s) | (y >> (64 - s));
}

/* ax = n pi/2 + rh + rl for finite ax > pi/4, |rh| <= pi/4 (1 + 2^-30); returns n mod 4.
 * Cody-Waite with pi/2 in four parts below 2^20, Payne-Hanek (bits of 2/pi) above. */
static inline int chaplygin_dm__rem_pio2(double ax, double *rh, double *rl)
{
    if (ax < 0x1p20) {
        double nd = (ax * chaplygin_dm_INV_PIO2 + CHAPLYGIN_DM_SHIFT) - CHAPLYGIN_DM_SHIFT;
        int n = (int)nd;
        double t1 = ax - nd * chaplygin_dm_CW_P1; /* exact: n P1 exact, Sterbenz */
        double e2, e3, t2, t3, lo;
        t2 = chaplygin_dm__two_sum(t1, -(nd * chaplygin_dm_CW_P2), &e2);
        t3 = chaplygin_dm__two_sum(t2, -(nd * chaplygin_dm_CW_P3), &e3);
        lo = (e2 + e3) - nd * chaplygin_dm_CW_P4;
        *rh = chaplygin_dm__fast_two_sum(t3, lo, rl);
        return n & 3;
    } else {
        /* ax = M 2^E, M < 2^53. Window W of 192 bits of 2/pi starting at bit E - 1 after the
         * point: M W mod 2^192 = (n mod 4) 2^190 + F, x 2/pi = n + F 2^-190 (mod 4) with an
         * error below 2^-137. */
        const uint64_t *T = chaplygin_dm_TWO_OVER_PI_BITS;
        uint64_t ix = chaplygin_dm__bits(ax);
        int ex = (int)(ix >> 52) - 1023;
        uint64_t M = (ix & UINT64_C(0x000fffffffffffff)) | UINT64_C(0x0010000000000000);
        int t0 = ex + 10; /* bit index in the table (bit 64 is the first bit after the point) */
        int q = t0 >> 6, s = t0 & 63;
        uint64_t w0 = chaplygin_dm__shl2(T[q], T[q + 1], s);
        uint64_t w1 = chaplygin_dm__shl2(T[q + 1], T[q + 2], s);
        uint64_t w2 = chaplygin_dm__shl2(T[q + 2], T[q + 3], s);
        uint64_t hi1, hi2, lo1, lo2, r0, r1, r2, a, b;
        int n, neg = 0, z, sh = 0;
        double fh, fl, ph, pe, lo, h, l;
        lo2 = chaplygin_dm__mul64(M, w2, &hi2);
        lo1 = chaplygin_dm__mul64(M, w1, &hi1);
        r2 = lo2;
        r1 = lo1 + hi2;
        r0 = M * w0 + hi1 + (uint64_t)(r1 < hi2);
        n = (int)(r0 >> 62);
        r0 &= UINT64_C(0x3fffffffffffffff);
        if (r0 >> 61) { /* fraction >= 1/2: n + 1 and F - 2^190 */
            uint64_t c2, c1;
            n += 1;
            neg = 1;
            r2 = ~r2 + 1u;
            c2 = (uint64_t)(r2 == 0);
            r1 = ~r1 + c2;
            c1 = c2 & (uint64_t)(r1 == 0);
            r0 = (~r0 + c1) & UINT64_C(0x3fffffffffffffff);
        }
        if (r0 == 0) { /* F < 2^128: not reached by doubles (|r| >= 2^-62), kept for safety */
            r0 = r1;
            r1 = r2;
            r2 = 0;
            sh = 64;
        }
        z = chaplygin_dm__clz64(r0);
        a = chaplygin_dm__shl2(r0, r1, z);
        b = chaplygin_dm__shl2(r1, r2, z);
        /* F 2^-190 = (a 2^64 + b) 2^(-126 - z - sh): 106 leading bits as fh + fl */
        fh = (double)(a >> 11) * chaplygin_dm__pow2(-51 - z - sh);
        fl = (double)(((a & 0x7ffu) << 42) | (b >> 22)) * chaplygin_dm__pow2(-104 - z - sh);
        ph = chaplygin_dm__two_prod(fh, chaplygin_dm_PIO2_HI, &pe);
        lo = pe + (fh * chaplygin_dm_PIO2_LO + fl * chaplygin_dm_PIO2_HI);
        h = chaplygin_dm__fast_two_sum(ph, lo, &l);
        *rh = neg ? -h : h;
        *rl = neg ? -l : l;
        return n & 3;
    }
}

/* The table path of the kernels, 1/8 <= |rh| <= pi/4 (1 + 2^-30): |r| = a + d with a = i/128,
 * |d| <= 1/256; returns the sign of r and fills d = dh + *xl, sin d - d (*sd, without xl) and
 * cos d - 1 (*cd), and the table row *i. */
static inline double chaplygin_dm__trig_split(double rh, double rl, double *xl, double *dh,
                                              double *sd, double *cd, int *i)
{
    double sg = rh < 0.0 ? -1.0 : 1.0;
    double xh = sg * rh;
    double id = (xh * 128.0 + CHAPLYGIN_DM_SHIFT) - CHAPLYGIN_DM_SHIFT;
    double dz;
    *xl = sg * rl;
    *i = (int)id - 16;
    *dh = xh - id * 0x1p-7; /* exact */
    dz = *dh * *dh;
    *sd = (*dh * dz) * (chaplygin_dm_SIND_POLY[0] + dz * chaplygin_dm_SIND_POLY[1]);
    *cd = dz * (chaplygin_dm_COSD_POLY[0] +
                dz * (chaplygin_dm_COSD_POLY[1] + dz * chaplygin_dm_COSD_POLY[2]));
    return sg;
}

/* sin(rh + rl) for |rh| <= pi/4 (1 + 2^-30), rh != 0. */
static inline double chaplygin_dm__sin_kernel(double rh, double rl)
{
    if (fabs(rh) < 0.125) {
        const double *c = chaplygin_dm_SIN_POLY;
        double z = rh * rh, z2 = z * z;
        double P = (c[0] + z * c[1]) + z2 * ((c[2] + z * c[3]) + z2 * c[4]);
        return rh + (rl + ((rh * z) * P - (0.5 * z) * rl));
    } else { /* sin(a + d) = S + C d + S (cos d - 1) + C (sin d - d) */
        double xl, dh, sd, cd, S, Sl, C, Cl, e, s, tail;
        int i;
        double sg = chaplygin_dm__trig_split(rh, rl, &xl, &dh, &sd, &cd, &i);
        S = chaplygin_dm_TRIG_S_HI[i];
        Sl = chaplygin_dm_TRIG_S_LO[i];
        C = chaplygin_dm_TRIG_C_HI[i];
        Cl = chaplygin_dm_TRIG_C_LO[i];
        s = chaplygin_dm__fast_two_sum(S, C * dh, &e);
        tail = Sl + (C * xl + Cl * dh) + (S * cd + C * sd);
        return sg * (s + (e + tail));
    }
}

/* cos(rh + rl) for |rh| <= pi/4 (1 + 2^-30). */
static inline double chaplygin_dm__cos_kernel(double rh, double rl)
{
    if (fabs(rh) < 0.125) {
        const double *c = chaplygin_dm_COS_POLY;
        double z = rh * rh, z2 = z * z;
        double hz = 0.5 * z;
        double w = 1.0 - hz;
        double err = (1.0 - w) - hz; /* exact */
        double Q = (c[1] + z * c[2]) + z2 * (c[3] + z * c[4]);
        return w + (err + (z2 * Q - rh * rl));
    } else { /* cos(a + d) = C - S d + C (cos d - 1) - S (sin d - d) */
        double xl, dh, sd, cd, S, Sl, C, Cl, e, s, tail;
        int i;
        chaplygin_dm__trig_split(rh, rl, &xl, &dh, &sd, &cd, &i);
        S = chaplygin_dm_TRIG_S_HI[i];
        Sl = chaplygin_dm_TRIG_S_LO[i];
        C = chaplygin_dm_TRIG_C_HI[i];
        Cl = chaplygin_dm_TRIG_C_LO[i];
        s = chaplygin_dm__fast_two_sum(C, -(S * dh), &e);
        tail = Cl - (S * xl + Sl * dh) + (C * cd - S * sd);
        return s + (e + tail);
    }
}

/* sin (odd = 0) or cos (odd = 1) of |x| > 2^-27 finite: the quadrant's kernel and sign. */
static inline double chaplygin_dm__sincos(double ax, int odd)
{
    double rh, rl, v;
    int n;
    if (ax <= chaplygin_dm_PI_O4) {
        n = 0;
        rh = ax;
        rl = 0.0;
    } else {
        n = chaplygin_dm__rem_pio2(ax, &rh, &rl);
    }
    n += odd;
    v = (n & 1) ? chaplygin_dm__cos_kernel(rh, rl) : chaplygin_dm__sin_kernel(rh, rl);
    return (n & 2) ? -v : v;
}

static inline double chaplygin_sin(double x)
{
    double ax = fabs(x), v;
    if (ax < 0x1p-27) /* sin x = x (1 - x^2/6): rounds to x; keeps -0 */
        return x;
    if (!(ax < chaplygin_dm__inf()))
        return chaplygin_dm__nan();
    v = chaplygin_dm__sincos(ax, 0);
    return x < 0.0 ? -v : v;
}

static inline double chaplygin_cos(double x)
{
    double ax = fabs(x);
    if (ax < 0x1p-27) /* cos x = 1 - x^2/2 rounds to 1 */
        return 1.0;
    if (!(ax < chaplygin_dm__inf()))
        return chaplygin_dm__nan();
    return chaplygin_dm__sincos(ax, 1);
}

/* ------------------------------------------------------------------ atan, atan2, asin, acos */

/* atan(u/v) = h + *l for u = uh + ul, v = vh + vl with 0 <= u <= v (1 + 2^-50), 2^-70 <= vh <=
 * 2^70 and u/v >= 2^-64 or u = 0: c = i/64 nearest to u/v, t = (u - c v)/(v + c u) as a
 * double-double, |t| <= 1/128, atan(u/v) = atan(c) + atan(t). */
static inline double chaplygin_dm__atan_kernel(double uh, double ul, double vh, double vl,
                                                double *l)
{
    const double *c = chaplygin_dm_ATAN_POLY;
    double q = uh / vh;
    double id = (q * 64.0 + CHAPLYGIN_DM_SHIFT) - CHAPLYGIN_DM_SHIFT;
    int i = (int)id;
    double ci = id * 0x1p-6;
    double vhh = chaplygin_dm__double(chaplygin_dm__bits(vh) & ~UINT64_C(0x3f)); /* 47 bits */
    double vhl = vh - vhh;
    double uhh = chaplygin_dm__double(chaplygin_dm__bits(uh) & ~UINT64_C(0x3f));
    double uhl = uh - uhh;
    double n1 = uh - ci * vhh; /* exact: ci vhh exact, Sterbenz */
    double ne, N1 = chaplygin_dm__two_sum(n1, -(ci * vhl), &ne);
    double Nl = ne + (ul - ci * vl);
    double de, D1 = chaplygin_dm__fast_two_sum(vh, ci * uhh, &de);
    double Dl = de + (ci * uhl + (vl + ci * ul));
    double inv = 1.0 / D1;
    double th = N1 * inv;
    double pe, p = chaplygin_dm__two_prod(th, D1, &pe);
    double tl = (((N1 - p) - pe) + (Nl - th * Dl)) * inv;
    double z = th * th;
    double P = (c[0] + z * c[1]) + (z * z) * (c[2] + z * c[3]);
    double tail = tl + (th * z) * P;
    double e, h = chaplygin_dm__fast_two_sum(chaplygin_dm_ATAN_HI[i], th, &e);
    *l = e + (chaplygin_dm_ATAN_LO[i] + tail);
    return h;
}

static inline double chaplygin_atan(double x)
{
    double ax = fabs(x), h, l, res;
    if (ax < 0x1p-27) /* atan x = x (1 - x^2/3): rounds to x; keeps -0 */
        return x;
    if (!(ax <= 0x1p60)) { /* atan x = pi/2 - 1/x rounds to pi/2 */
        if (ax != ax)
            return chaplygin_dm__nan();
        return x < 0.0 ? -chaplygin_dm_PIO2_HI : chaplygin_dm_PIO2_HI;
    }
    if (ax <= 1.0) {
        h = chaplygin_dm__atan_kernel(ax, 0.0, 1.0, 0.0, &l);
        res = h + l;
    } else { /* pi/2 - atan(1/ax) */
        double e, s;
        h = chaplygin_dm__atan_kernel(1.0, 0.0, ax, 0.0, &l);
        s = chaplygin_dm__fast_two_sum(chaplygin_dm_PIO2_HI, -h, &e);
        res = s + (e + (chaplygin_dm_PIO2_LO - l));
    }
    return x < 0.0 ? -res : res;
}

/* base + sign (h + l), rounded once (base = bh + bl is 0, pi/2 or pi, sign = +-1). */
static inline double chaplygin_dm__angle(double bh, double bl, double sign, double h, double l)
{
    double e, s = chaplygin_dm__fast_two_sum(bh, sign * h, &e);
    return s + (e + (bl + sign * l));
}

static inline double chaplygin_atan2(double y, double x)
{
    double ax = fabs(x), ay = fabs(y), res;
    int xneg = (int)(chaplygin_dm__bits(x) >> 63);
    if (x != x || y != y)
        return chaplygin_dm__nan();
    if (ay == 0.0) /* atan2(+-0, +0 or x > 0) = +-0, atan2(+-0, -0 or x < 0) = +-pi */
        res = xneg ? chaplygin_dm_PI_HI : 0.0;
    else if (ax == 0.0)
        res = chaplygin_dm_PIO2_HI;
    else if (ax == chaplygin_dm__inf()) {
        if (ay == chaplygin_dm__inf())
            res = xneg ? chaplygin_dm_PI3O4 : chaplygin_dm_PI_O4;
        else
            res = xneg ? chaplygin_dm_PI_HI : 0.0;
    } else if (ay == chaplygin_dm__inf())
        res = chaplygin_dm_PIO2_HI;
    else {
        int swap = ay > ax;
        double u = swap ? ax : ay, v = swap ? ay : ax;
        double su = u, sv = v, f, h, l, bh, bl, sign;
        int k;
        if (sv > 0x1p1000) {
            su *= 0x1p-600;
            sv *= 0x1p-600;
        } else if (sv < 0x1p-1000) {
            su *= 0x1p600;
            sv *= 0x1p600;
        }
        k = (int)(chaplygin_dm__bits(sv) >> 52) - 1023;
        f = chaplygin_dm__pow2(-k); /* sv in [1, 2) */
        su *= f;
        sv *= f;
        if (su < 0x1p-62) { /* atan(u/v) = u/v (1 - (u/v)^2/3) */
            h = u / v;
            l = 0.0;
        } else {
            h = chaplygin_dm__atan_kernel(su, 0.0, sv, 0.0, &l);
        }
        /* theta = atan(u/v) (x > 0, |y| <= |x|), pi/2 -+ atan(u/v) (|y| > |x|), pi - atan */
        if (swap) {
            bh = chaplygin_dm_PIO2_HI;
            bl = chaplygin_dm_PIO2_LO;
            sign = xneg ? 1.0 : -1.0;
        } else if (xneg) {
            bh = chaplygin_dm_PI_HI;
            bl = chaplygin_dm_PI_LO;
            sign = -1.0;
        } else {
            bh = 0.0;
            bl = 0.0;
            sign = 1.0;
        }
        res = chaplygin_dm__angle(bh, bl, sign, h, l);
    }
    return (chaplygin_dm__bits(y) >> 63) ? -res : res;
}

/* sqrt(1 - ax^2) = sh + *sl for 2^-60 <= ax < 1: (1 - ax)(1 + ax) as a double-double. */
static inline double chaplygin_dm__sqrt1mx2(double ax, double *sl)
{
    double de, d = chaplygin_dm__fast_two_sum(1.0, -ax, &de); /* 1 - ax */
    double ae, a = chaplygin_dm__fast_two_sum(1.0, ax, &ae);  /* 1 + ax */
    double pe, wh = chaplygin_dm__two_prod(d, a, &pe);
    double wl = pe + (d * ae + de * a), s, q, qe;
    s = sqrt(wh);
    q = chaplygin_dm__two_prod(s, s, &qe);
    *sl = (((wh - q) - qe) + wl) / (s + s);
    return s;
}

static inline double chaplygin_asin(double x)
{
    double ax = fabs(x), sh, sl, h, l, res;
    if (!(ax <= 1.0))
        return chaplygin_dm__nan();
    if (ax < 0x1p-27) /* asin x = x (1 + x^2/6): rounds to x; keeps -0 */
        return x;
    if (ax == 1.0)
        res = chaplygin_dm_PIO2_HI;
    else { /* atan(|x| / s) if |x| <= s = sqrt(1 - x^2), else pi/2 - atan(s / |x|); selects */
        int first;
        sh = chaplygin_dm__sqrt1mx2(ax, &sl);
        first = ax <= sh;
        h = chaplygin_dm__atan_kernel(first ? ax : sh, first ? 0.0 : sl, first ? sh : ax,
                                      first ? sl : 0.0, &l);
        res = chaplygin_dm__angle(first ? 0.0 : chaplygin_dm_PIO2_HI,
                                  first ? 0.0 : chaplygin_dm_PIO2_LO, first ? 1.0 : -1.0, h, l);
    }
    return x < 0.0 ? -res : res;
}

static inline double chaplygin_acos(double x)
{
    double ax = fabs(x), sh, sl, h, l, bh, bl;
    int xneg = x < 0.0, first;
    if (!(ax <= 1.0))
        return chaplygin_dm__nan();
    if (ax < 0x1p-60) /* pi/2 - x rounds to pi/2 */
        return chaplygin_dm_PIO2_HI;
    if (ax == 1.0)
        return xneg ? chaplygin_dm_PI_HI : 0.0;
    sh = chaplygin_dm__sqrt1mx2(ax, &sl);
    /* acos |x| = atan(s / |x|) with s = sqrt(1 - x^2), or pi/2 - atan(|x| / s) when s > |x|;
     * acos x = pi - acos |x| for x < 0 (selects, no branch) */
    first = sh <= ax;
    h = chaplygin_dm__atan_kernel(first ? sh : ax, first ? sl : 0.0, first ? ax : sh,
                                  first ? 0.0 : sl, &l);
    if (first) {
        bh = xneg ? chaplygin_dm_PI_HI : 0.0;
        bl = xneg ? chaplygin_dm_PI_LO : 0.0;
    } else {
        bh = chaplygin_dm_PIO2_HI;
        bl = chaplygin_dm_PIO2_LO;
    }
    return chaplygin_dm__angle(bh, bl, first == xneg ? -1.0 : 1.0, h, l);
}

/* --------------------------------------------------------------------------------------- cbrt */

/* Cube root: a starting guess (polynomial, 2^-19), one Halley step (~2^-52), one Newton step with
 * the residual a - y^3 formed exactly. */
static inline double chaplygin_cbrt(double x)
{
    const double *c = chaplygin_dm_CBRT_POLY;
    double ax = fabs(x), m, a, y, y3, p, pe, cc, ce, res, r;
    uint64_t ia;
    int e, q, j, adj = 0;
    if (ax == 0.0 || ax == chaplygin_dm__inf())
        return x;
    if (ax != ax)
        return chaplygin_dm__nan();
    if (ax < 0x1p-1022) { /* subnormal: 2^54 = (2^18)^3 */
        ax *= 0x1p54;
        adj = -18;
    }
    ia = chaplygin_dm__bits(ax);
    e = (int)(ia >> 52) - 1023;
    m = chaplygin_dm__double((ia & UINT64_C(0x000fffffffffffff)) | UINT64_C(0x3ff0000000000000));
    q = (e + 3075) / 3 - 1025; /* floor(e / 3) */
    j = e - 3 * q;
    a = m * chaplygin_dm__pow2(j); /* ax = a 2^(3q), a in [1, 8) */
    y = (((((c[0] * m + c[1]) * m + c[2]) * m + c[3]) * m + c[4]) * m + c[5]) *
        chaplygin_dm_CBRT_2J[j];
    y3 = (y * y) * y;
    y = y * ((y3 + 2.0 * a) / (2.0 * y3 + a)); /* Halley */
    p = chaplygin_dm__two_prod(y, y, &pe);
    cc = chaplygin_dm__two_prod(y, p, &ce);
    res = ((a - cc) - ce) - y * pe; /* a - y^3 */
    r = (y + res / (3.0 * p)) * chaplygin_dm__pow2(q + adj);
    return x < 0.0 ? -r : r;
}

/* -------------------------------------------------------------------------------------- hypot */

/* sqrt(x^2 + y^2) without undue overflow or underflow: the sum of squares as a double-double,
 * its square root corrected once, one final rounding (also to a subnormal result). */
static inline double chaplygin_hypot(double x, double y)
{
    double ax = fabs(x), ay = fabs(y), M, m, f, a, ae, b, be, s, se, t, wh, wl, r, q, qe, corr,
           hh, hl;
    int K = 0, k;
    if (ax == chaplygin_dm__inf() || ay == chaplygin_dm__inf())
        return chaplygin_dm__inf();
    if (ax != ax || ay != ay)
        return chaplygin_dm__nan();
    M = ax > ay ? ax : ay;
    m = ax > ay ? ay : ax;
    if (m == 0.0)
        return M;
    if (M > 0x1p1000) {
        M *= 0x1p-600;
        m *= 0x1p-600;
        K = 600;
    } else if (M < 0x1p-1000) {
        M *= 0x1p600;
        m *= 0x1p600;
        K = -600;
    }
    k = (int)(chaplygin_dm__bits(M) >> 52) - 1023;
    f = chaplygin_dm__pow2(-k); /* M in [1, 2) */
    M *= f;
    m *= f;
    K += k;
    if (m < 0x1p-60) /* sqrt(M^2 + m^2) = M (1 + m^2/(2 M^2)) rounds to M */
        return ax > ay ? ax : ay;
    a = chaplygin_dm__two_prod(M, M, &ae);
    b = chaplygin_dm__two_prod(m, m, &be);
    s = chaplygin_dm__fast_two_sum(a, b, &se);
    t = se + (ae + be);
    wh = chaplygin_dm__fast_two_sum(s, t, &wl);
    r = sqrt(wh);
    q = chaplygin_dm__two_prod(r, r, &qe);
    corr = (((wh - q) - qe) + wl) / (r + r);
    hh = chaplygin_dm__fast_two_sum(r, corr, &hl);
    return chaplygin_dm__scale(hh, hl, K);
}

/* --------------------------------------------------------------------------------- sinh, cosh */

/* e^ax and e^-ax as double-doubles (eh + *el, ih + *il) for 2^-28 <= ax <= 23. */
static inline double chaplygin_dm__exp_pm(double ax, double *el, double *ih, double *il)
{
    double h, l, f;
    int m;
    h = chaplygin_dm__exp_kernel(-ax, 0.0, &l, &m);
    f = chaplygin_dm__pow2(m);
    *ih = h * f;
    *il = l * f;
    h = chaplygin_dm__exp_kernel(ax, 0.0, &l, &m);
    f = chaplygin_dm__pow2(m);
    *el = l * f;
    return h * f;
}

static inline double chaplygin_sinh(double x)
{
    double ax = fabs(x), res;
    if (ax < 0.25) { /* Taylor: x + x^3/3! + ... + x^13/13! */
        const double *c = chaplygin_dm_SINH_POLY;
        double z = ax * ax, z2 = z * z;
        double P = ((c[0] + z * c[1]) + z2 * (c[2] + z * c[3])) + (z2 * z2) * (c[4] + z * c[5]);
        res = ax + (ax * z) * P;
    } else if (ax != ax) {
        return chaplygin_dm__nan();
    } else if (ax > 22.0) { /* e^-x below 2^-63 e^x: e^x / 2 */
        double h, l;
        int m;
        if (ax > 711.0)
            res = chaplygin_dm__inf();
        else {
            h = chaplygin_dm__exp_kernel(ax, 0.0, &l, &m);
            res = chaplygin_dm__scale(h, l, m - 1);
        }
    } else { /* (e^x - e^-x) / 2 */
        double el, ih, il, e, s, eh = chaplygin_dm__exp_pm(ax, &el, &ih, &il);
        s = chaplygin_dm__fast_two_sum(eh, -ih, &e);
        res = 0.5 * (s + (e + (el - il)));
    }
    return (chaplygin_dm__bits(x) >> 63) ? -res : res; /* sinh(-0) = -0 */
}

static inline double chaplygin_cosh(double x)
{
    double ax = fabs(x), el, ih, il, e, s, eh;
    if (ax != ax)
        return chaplygin_dm__nan();
    if (ax < 0x1p-27) /* 1 + x^2/2 rounds to 1 */
        return 1.0;
    if (ax > 22.0) {
        double h, l;
        int m;
        if (ax > 711.0)
            return chaplygin_dm__inf();
        h = chaplygin_dm__exp_kernel(ax, 0.0, &l, &m);
        return chaplygin_dm__scale(h, l, m - 1);
    }
    eh = chaplygin_dm__exp_pm(ax, &el, &ih, &il);
    s = chaplygin_dm__fast_two_sum(eh, ih, &e);
    return 0.5 * (s + (e + (el + il)));
}

#endif /* CHAPLYGIN_DETMATH_H */
