/* SPDX-License-Identifier: MIT */
/* Physical values to and from Q15 (pf_q15.h). Double arithmetic: host and
 * FPU builds only, never on the integer-only M0+ path. */
#include "pneufrac/pf_q15.h"

int16_t pf_q15_quantize(double v, double full_scale)
{
    double x, r;
    /* NaN and infinite full scales fail both comparisons. */
    if (!(full_scale > 0.0 && full_scale <= 1.7976931348623157e308))
        return 0;
    x = v / full_scale * 32768.0;
    if (x != x)
        return 0;
    if (!(x < 32767.0))
        return INT16_MAX;
    if (!(x > -32768.0))
        return INT16_MIN;
    /* Round half up without floor() (no libm): the cast truncates toward
     * zero, so step back one for negative non-integers. floor(x + 0.5)
     * would round 0.49999999999999994 up: the sum itself rounds. */
    r = (double)(long)x;
    if (r > x)
        r -= 1.0;
    if (x - r >= 0.5)
        r += 1.0;
    return (int16_t)r;
}

double pf_q15_value(int16_t q, double full_scale)
{
    return (double)q * full_scale / 32768.0;
}
