#!/usr/bin/env python3
"""Writes the per-Q macro families of the host IQmath to stdout:
  tools/gen_qn_families.py iq    > iqmath_qn_fixed.h
  tools/gen_qn_families.py float > iqmath_qn_float.h
"""
import sys
mode = sys.argv[1]
out = []
def fam(title, fmt, ns=range(30, 0, -1)):
    out.append("/* %s */" % title)
    for n in ns:
        out.append(fmt.format(n=n))
    out.append("")
if mode == "iq":
    fam("_IQN(A): float constant/expression to IQN (truncates toward 0, as TI)",
        "#define _IQ{n}(A)          IQM_FTOQ((A), {n})")
    fam("_IQNtoF(A): IQN to float", "#define _IQ{n}toF(A)       iqm_qtof((A), {n})")
    fam("_IQtoIQN(A): GLOBAL_Q to IQN (left shift wraps, right shift floors)",
        "#define _IQtoIQ{n}(A)      IQM_CALL(IQMATH_FN_TOIQN, iqm_qtoq((A), GLOBAL_Q, {n}))")
    fam("_IQNtoIQ(A): IQN to GLOBAL_Q",
        "#define _IQ{n}toIQ(A)      IQM_CALL(IQMATH_FN_TOIQN, iqm_qtoq((A), {n}, GLOBAL_Q))")
    fam("_IQtoQN(A): GLOBAL_Q to 16-bit QN (value returned as int32_t, as TI's long)",
        "#define _IQtoQ{n}(A)       IQM_CALL(IQMATH_FN_TOQN, iqm_qtoq((A), GLOBAL_Q, {n}))", range(15, 0, -1))
    fam("_QNtoIQ(A): 16-bit QN to GLOBAL_Q",
        "#define _Q{n}toIQ(A)       IQM_CALL(IQMATH_FN_TOQN, iqm_qtoq((int32_t)(A), {n}, GLOBAL_Q))", range(15, 0, -1))
    for name, fn, args, call in [
        ("mpy", "MPY", "A, B", "iqm_mpy((A), (B), {n})"),
        ("rmpy", "RMPY", "A, B", "iqm_rmpy((A), (B), {n})"),
        ("rsmpy", "RSMPY", "A, B", "iqm_rsmpy((A), (B), {n})"),
        ("mpyI32", "MPYI32", "A, B", "iqm_mpyI32((A), (B))"),
        ("mpyI32int", "MPYI32INT", "A, B", "iqm_mpyI32int((A), (B), {n})"),
        ("mpyI32frac", "MPYI32FRAC", "A, B", "iqm_mpyI32frac((A), (B), {n})"),
        ("div", "DIV", "A, B", "iqm_div((A), (B), {n})"),
        ("sqrt", "SQRT", "A", "iqm_sqrt((A), {n})"),
        ("isqrt", "ISQRT", "A", "iqm_isqrt((A), {n})"),
        ("mag", "MAG", "A, B", "iqm_mag((A), (B))"),
        ("sin", "SIN", "A", "iqm_sin((A), {n})"),
        ("cos", "COS", "A", "iqm_cos((A), {n})"),
        ("sinPU", "SINPU", "A", "iqm_sinpu((A), {n})"),
        ("cosPU", "COSPU", "A", "iqm_cospu((A), {n})"),
        ("atan2", "ATAN2", "A, B", "iqm_atan2((A), (B), {n})"),
        ("atan2PU", "ATAN2PU", "A, B", "iqm_atan2pu((A), (B), {n})"),
        ("atan", "ATAN", "A", "iqm_atan2((A), IQM_ONE({n}), {n})"),
        ("int", "INT", "A", "iqm_int((A), {n})"),
        ("frac", "FRAC", "A", "iqm_frac((A), {n})"),
        ("abs", "ABS", "A", "iqm_abs(A)"),
        ("mpyIQX", "MPYIQX", "A, IQA, B, IQB", "iqm_mpyiqx((A), (IQA), (B), (IQB), {n})"),
    ]:
        ns = range(30, 0, -1)
        if name in ("sin", "cos", "atan2", "atan"):
            ns = range(29, 0, -1)   # as TI: output range +-pi needs Q29 at most
        fam("_IQN%s(%s)" % (name, args),
            "#define _IQ{n}%s(%s)%s IQM_CALL(IQMATH_FN_%s, %s)" % (name, args, " " * max(1, 12 - len(name) - len(args)), fn, call), ns)
else:
    fam("_IQN(A)", "#define _IQ{n}(A)          ((float)(A))")
    fam("_IQNtoF(A)", "#define _IQ{n}toF(A)       ((float)(A))")
    fam("_IQtoIQN(A)", "#define _IQtoIQ{n}(A)      (A)")
    fam("_IQNtoIQ(A)", "#define _IQ{n}toIQ(A)      (A)")
    out.append("/* _IQtoQN(A) */")
    out2 = []
    for n in range(15, 0, -1):
        out2.append("#define _IQtoQ%d(A)       ((int32_t)((A) * %.1ff))" % (n, 2.0**n))
    out += out2 + [""]
    out.append("/* _QNtoIQ(A) */")
    for n in range(15, 0, -1):
        out.append("#define _Q%dtoIQ(A)       ((float)(A) * %.12gf)" % (n, 2.0**-n))
    out.append("")
    for name, args, expr in [
        ("mpy", "A, B", "((A) * (B))"),
        ("rmpy", "A, B", "((A) * (B))"),
        ("rsmpy", "A, B", "((A) * (B))"),
        ("mpyI32", "A, B", "((A) * (float)(B))"),
        ("mpyI32int", "A, B", "iqf_mpyI32int((A), (B))"),
        ("mpyI32frac", "A, B", "iqf_mpyI32frac((A), (B))"),
        ("div", "A, B", "((A) / (B))"),
        ("sqrt", "A", "sqrtf(A)"),
        ("isqrt", "A", "(1.0f / sqrtf(A))"),
        ("mag", "A, B", "iqf_mag((A), (B))"),
        ("sin", "A", "sinf(A)"),
        ("cos", "A", "cosf(A)"),
        ("sinPU", "A", "sinf((A) * IQF_2PI)"),
        ("cosPU", "A", "cosf((A) * IQF_2PI)"),
        ("atan2", "A, B", "atan2f((A), (B))"),
        ("atan2PU", "A, B", "iqf_atan2pu((A), (B))"),
        ("atan", "A", "atanf(A)"),
        ("int", "A", "((int32_t)(A))"),
        ("frac", "A", "iqf_frac(A)"),
        ("abs", "A", "fabsf(A)"),
        ("mpyIQX", "A, IQA, B, IQB", "((A) * (B))"),
    ]:
        ns = range(30, 0, -1)
        if name in ("sin", "cos", "atan2", "atan"):
            ns = range(29, 0, -1)
        fam("_IQN%s(%s)" % (name, args),
            "#define _IQ{n}%s(%s)%s %s" % (name, args, " " * max(1, 12 - len(name) - len(args)), expr), ns)
fname = "iqmath_qn_fixed.h" if mode == "iq" else "iqmath_qn_float.h"
guard = fname.upper().replace(".", "_")
build = "IQ_MATH" if mode == "iq" else "FLOAT_MATH"
print("""/**
 * @file %s
 * The per-Q families (_IQ30mpy ... _IQ1mpy and so on) of the host IQmath,
 * %s build.  Included by IQmathLib.h only; do not include directly.
 * Mechanical text, generated by tools/gen_qn_families.py (run it with
 * argument "%s"); each macro is its GLOBAL_Q sibling in IQmathLib.h with
 * the Q fixed, and has the same scaling and overflow behaviour.
 */
#ifndef %s
#define %s
""" % (fname, build, mode, guard, guard))
print("\n".join(out))
print("#endif /* %s */" % guard)
