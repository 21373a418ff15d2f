/* scene_number.c — see scene_number.h. */
#include "tracer/io/scene_number.h"

#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Powers of ten exactly representable in float (10^10 < 2^24 * 2^10). */
static const float pow10f_exact[11] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f,
                                       1e6f, 1e7f, 1e8f, 1e9f, 1e10f};

const char *rt_parse_float(const char *p, const char *end, float *out)
{
    const char *s = p;
    bool neg = false;
    if (s < end && (*s == '+' || *s == '-'))
        neg = *s++ == '-';
    uint64_t mant = 0;
    int ndig = 0, exp10 = 0, any = 0;
    bool lost = false;   /* digits beyond 19 significant ones were dropped */
    while (s < end && (unsigned)(*s - '0') < 10) {
        any = 1;
        if (ndig < 19) {
            mant = mant * 10 + (uint64_t)(*s - '0');
            if (mant)
                ndig++;
        } else {
            exp10++;
            lost = true;
        }
        s++;
    }
    if (s < end && *s == '.') {
        s++;
        while (s < end && (unsigned)(*s - '0') < 10) {
            any = 1;
            if (ndig < 19) {
                mant = mant * 10 + (uint64_t)(*s - '0');
                if (mant)
                    ndig++;
                exp10--;
            } else {
                lost = true;
            }
            s++;
        }
    }
    if (!any)
        return NULL;
    if (s < end && (*s == 'e' || *s == 'E')) {
        const char *e = s + 1;
        bool eneg = false;
        if (e < end && (*e == '+' || *e == '-'))
            eneg = *e++ == '-';
        if (!(e < end && (unsigned)(*e - '0') < 10))
            return NULL;
        int ev = 0;
        while (e < end && (unsigned)(*e - '0') < 10) {
            if (ev < 100000)
                ev = ev * 10 + (*e - '0');
            e++;
        }
        exp10 += eneg ? -ev : ev;
        s = e;
    }
    float v;
    if (!lost && mant < (1u << 24) && exp10 >= -10 && exp10 <= 10) {
        v = (float)mant;   /* exact: mant < 2^24 */
        v = exp10 < 0 ? v / pow10f_exact[-exp10] : v * pow10f_exact[exp10];
        if (neg)
            v = -v;
    } else {
        char buf[128];
        size_t n = (size_t)(s - p);
        if (n >= sizeof buf)
            return NULL;
        memcpy(buf, p, n);
        buf[n] = 0;
        v = strtof(buf, NULL);
    }
    if (!isfinite(v))
        return NULL;
    *out = v;
    return s;
}

const char *rt_parse_int(const char *p, const char *end, long long *out)
{
    const char *s = p;
    bool neg = false;
    if (s < end && (*s == '+' || *s == '-'))
        neg = *s++ == '-';
    if (!(s < end && (unsigned)(*s - '0') < 10))
        return NULL;
    long long v = 0;
    while (s < end && (unsigned)(*s - '0') < 10) {
        if (v > (LLONG_MAX - 9) / 10)
            return NULL;
        v = v * 10 + (*s - '0');
        s++;
    }
    *out = neg ? -v : v;
    return s;
}
