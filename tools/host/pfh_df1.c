/* SPDX-License-Identifier: MIT */
#include "pfh_df1.h"

/* A stage's state {x[n-1], x[n-2], y[n-1], y[n-2]} after input x, output y:
 * the same for both arithmetics, whatever the element type. */
#define DF1_PUSH(s, x, y) \
    do {                  \
        (s)[1] = (s)[0];  \
        (s)[0] = (x);     \
        (s)[3] = (s)[2];  \
        (s)[2] = (y);     \
    } while (0)

void pfh_df1_run_f32(pfh_df1_f32 *f, const float *x, float *y, size_t len)
{
    size_t i;
    int k;
    for (i = 0; i < len; i++) {
        float v = x[i];
        for (k = 0; k < f->n; k++) {
            const float *c = f->c + 5 * k;
            float *s = f->st + 4 * k;
            float out = c[0] * v + c[1] * s[0] + c[2] * s[1] + c[3] * s[2] + c[4] * s[3];
            DF1_PUSH(s, v, out);
            v = out;
        }
        y[i] = v;
    }
}

/* acc >> sh rounded toward minus infinity (an arithmetic shift), without
 * shifting a negative number: |acc| < 2^36 here, so the bias keeps the
 * operand positive. */
static int64_t floor_shift(int64_t acc, int sh)
{
    const uint64_t bias = (uint64_t)1 << 40;
    return (int64_t)(((uint64_t)acc + bias) >> sh) - (int64_t)(bias >> sh);
}

static int16_t sat16(int64_t v)
{
    return (int16_t)(v > 32767 ? 32767 : (v < -32768 ? -32768 : v));
}

void pfh_df1_run_q15(pfh_df1_q15 *f, const int16_t *x, int16_t *y, size_t len)
{
    size_t i;
    int k;
    for (i = 0; i < len; i++) {
        int16_t v = x[i];
        for (k = 0; k < f->n; k++) {
            const int16_t *c = f->c + 6 * k;
            int16_t *s = f->st + 4 * k, out;
            int64_t acc = (int64_t)c[0] * v + (int64_t)c[2] * s[0] +
                          (int64_t)c[3] * s[1] + (int64_t)c[4] * s[2] +
                          (int64_t)c[5] * s[3];
            out = sat16(floor_shift(acc, 15 - f->post_shift));
            DF1_PUSH(s, v, out);
            v = out;
        }
        y[i] = v;
    }
}
