/* One expf for both sides of the co-simulation.
 *
 * drive_init computes filter coefficients with expf (src/sense/dc_bus.c,
 * src/sense/qep_speed.c).  glibc's and avr-libc's expf differ in the last
 * bit for some arguments (measured: 1 - expf(-2 pi 100 / 15000) is
 * 0x3D280770 on glibc, 0x3D280780 on avr-libc), which changes a Q24
 * coefficient by an LSB and the speed estimate after it, although the
 * fixed-point code is right.  So both builds link this implementation
 * instead of their libm's ("share the init constants"): float + - * only,
 * which are IEEE round-to-nearest on both, so the result is bit-identical,
 * and the step comparison then checks the fixed-point ISR path alone.
 * Accuracy: range reduction by ln 2 and a degree-7 Taylor polynomial on
 * |r| <= ln2/2: relative error < 2e-7 (~2 ulp), enough for filter
 * coefficients; TI's rts2800 expf on the target is a third implementation.
 * (avr-libc maps expf to exp, double being float there.) */
#include <math.h>

static float cosim_expf(float x)
{
    const float ln2 = 0.693147182f;
    float k, r, p, s = 1.0f;
    int n;
    if (x > 88.0f) { return 3.0e38f; }
    if (x < -87.0f) { return 0.0f; }
    k = (float)(int)(x / ln2 + (x < 0.0f ? -0.5f : 0.5f));
    r = x - k * ln2;
    p = 1.0f + r * (1.0f + r * (0.5f + r * (0.166666672f + r * (0.0416666679f
        + r * (0.00833333377f + r * (0.00138888892f + r * 0.000198412701f))))));
    for (n = (int)k; n > 0; n--) { s *= 2.0f; }
    for (n = (int)k; n < 0; n++) { s *= 0.5f; }
    return p * s;
}

#if defined(__AVR__)
double exp(double x)
{
    return cosim_expf(x);
}
#else
float expf(float x)
{
    return cosim_expf(x);
}
#endif
