/**
 * @file model_check.h
 * Assertion helpers for the model_* tests: print the measured value, the
 * reference and the bound, then assert, so that every run documents the
 * margins it passed with.
 */
#ifndef MODEL_CHECK_H
#define MODEL_CHECK_H

#include <math.h>
#include <stdio.h>

/* |meas - ref| <= tol_abs */
#define CHECK_ABS(what, meas, ref, tol_abs)                                        \
    do {                                                                           \
        const double m_ = (meas), r_ = (ref), t_ = (tol_abs);                      \
        printf("  %-44s meas % .9e ref % .9e |err| %.3e (bound %.1e)\n", (what),   \
               m_, r_, fabs(m_ - r_), t_);                                         \
        assert_true(fabs(m_ - r_) <= t_);                                          \
    } while (0)

/* |meas - ref| <= tol_rel * |ref| */
#define CHECK_REL(what, meas, ref, tol_rel)                                        \
    do {                                                                           \
        const double m_ = (meas), r_ = (ref), t_ = (tol_rel);                      \
        const double e_ = fabs(m_ - r_) / fabs(r_);                                \
        printf("  %-44s meas % .9e ref % .9e rel %.3e (bound %.1e)\n", (what), m_, \
               r_, e_, t_);                                                        \
        assert_true(e_ <= t_);                                                     \
    } while (0)

#endif /* MODEL_CHECK_H */
