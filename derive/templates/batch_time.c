static double bm_time(double t0, long k, double tau_hi, double tau_lo)
{
    const double kd = (double)k;
    const double p = kd * tau_hi;
    const double e = fma(kd, tau_hi, -p); /* exact error of the product */
    const double s = t0 + p;
    const double bb = s - t0;
    const double es = (t0 - (s - bb)) + (p - bb); /* exact error of the sum */
    return s + (es + e + kd * tau_lo);
}
