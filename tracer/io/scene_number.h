/* scene_number.h — fast decimal number parsing for the text scene readers.
 *
 * Contract: rt_parse_float parses one decimal number [+-]digits[.digits]
 * [(e|E)[+-]digits] (at least one digit in the mantissa) starting exactly at
 * p, reading no further than end, and returns the position after it, or NULL
 * when there is no number there or it is not finite as a float. The result
 * is the correctly rounded float (the same as strtof): exact float
 * arithmetic when the mantissa has <= 7 digits and |exponent| <= 10
 * (Clinger, "How to Read Floating Point Numbers Accurately", PLDI 1990,
 * fast path), strtof otherwise. rt_parse_int parses [+-]digits into a
 * long long (NULL on overflow or no digits). Neither skips whitespace. */
#ifndef RTSIM_TRACER_SCENE_NUMBER_H
#define RTSIM_TRACER_SCENE_NUMBER_H

const char *rt_parse_float(const char *p, const char *end, float *out);
const char *rt_parse_int(const char *p, const char *end, long long *out);

#endif
