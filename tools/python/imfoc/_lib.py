"""ctypes binding of include/imfoc_api.h (the shared library libimfoc.so).

The structs mirror the C header field by field; IMFOC_API_VERSION guards the
layout (a library built from another header version is refused).
"""
import ctypes as C
import os
from pathlib import Path

API_VERSION = 4
LIB_NAME = "libimfoc.so"

# tools/python/imfoc/_lib.py -> the repository root
REPO_ROOT = Path(__file__).resolve().parents[3]


class Info(C.Structure):
    _fields_ = [(n, C.c_double) for n in (
        "Ts_s", "I_base_A", "V_base_V", "f_base_Hz", "w_base_rad_s", "t_base_s",
        "Z_base_ohm", "L_base_H", "psi_base_Wb", "n_base_rpm",
        "current_full_scale_A", "vdc_full_scale_V")] + [
        ("t1pr", C.c_uint16), ("pole_pairs", C.c_uint16),
        ("encoder_lines", C.c_uint16), ("background_div", C.c_uint16)]


class RawIn(C.Structure):
    _fields_ = [("ia_raw", C.c_uint16), ("ib_raw", C.c_uint16), ("vdc_raw", C.c_uint16),
                ("qep_count", C.c_uint16), ("trip", C.c_uint16)]


class PhysIn(C.Structure):
    _fields_ = [("ia_A", C.c_double), ("ib_A", C.c_double), ("vdc_V", C.c_double),
                ("theta_m_rad", C.c_double), ("trip", C.c_uint16)]


class Out(C.Structure):
    _fields_ = [("cmpr", C.c_uint16 * 3), ("pwm_on", C.c_uint16),
                ("duty", C.c_double * 3), ("v_phase_V", C.c_double * 3)]


_SIGNAL_DOUBLES_1 = ("speed_rpm", "speed_ref_rpm", "ia_A", "ib_A", "vdc_V", "i_m_A", "i_t_A",
                     "i_mr_A", "theta_e_rad", "w_frame_rad_s", "u_alpha_V", "u_beta_V",
                     "u_m_ref_V", "u_t_ref_V")
_SIGNAL_REG = ("y1", "y2", "i_mf", "u_mf", "i_tf", "u_tf", "wr_f")
PARAM_NAMES = ("Rs_ohm", "Rr_ohm", "Lm_H", "Lr_H", "psi_r_Wb", "Tr_s")
CONF_NAMES = ("Rs", "Rr", "Lm", "Lr", "psi_r", "Tr")   # imfoc_signals_t.conf_*, PARAM_NAMES' order


class Signals(C.Structure):
    _fields_ = ([("isr_count", C.c_uint32)] +
                [(n, C.c_uint16) for n in ("state", "fault", "pwm_on", "params_valid",
                                           "live_valid", "rls_on")] +
                [(n, C.c_double) for n in _SIGNAL_DOUBLES_1] +
                [("K", C.c_double * 4)] +
                [(n, C.c_double) for n in _SIGNAL_REG] +
                [("rls_updates", C.c_uint32)] +
                [("live_" + n, C.c_double) for n in PARAM_NAMES] +
                [(n, C.c_double) for n in PARAM_NAMES] +
                # the adaptive sequence (API version 2)
                [(n, C.c_uint16) for n in ("pass_", "track_valid", "params_tracked")] +
                [(n, C.c_double) for n in ("Rs_dc_ohm", "sigma_ls_dc_H", "Rr_track_ohm",
                                           "Tr_track_s")] +
                # API version 3: the last extraction (Rs_ohm.. above are the published set)
                [("extract_valid", C.c_uint16)] +
                [("extract_" + n, C.c_double) for n in PARAM_NAMES] +
                # API version 4: the publication's verdict and confidences
                [("publish_reason", C.c_uint16)] +
                [("conf_" + n, C.c_double) for n in CONF_NAMES] +
                [(n, C.c_double) for n in ("conf_residual", "conf_amplification",
                                           "conf_excitation")])


def find_library():
    """Path of libimfoc.so, the first of:
      $IMFOC_LIB      the library file itself (wins over the next);
      $IMFOC_LIB_DIR  a build directory (its host_sim/api/) or the library's own directory;
      the repository's build/host-iq."""
    env = os.environ.get("IMFOC_LIB")
    if env:
        if not Path(env).is_file():
            raise FileNotFoundError(f"IMFOC_LIB={env} is not a file (it names the library "
                                    f"itself; IMFOC_LIB_DIR names a build directory)")
        return Path(env)
    dirs = []
    if os.environ.get("IMFOC_LIB_DIR"):
        d = Path(os.environ["IMFOC_LIB_DIR"])
        dirs += [d / "host_sim" / "api", d]
    dirs.append(REPO_ROOT / "build" / "host-iq" / "host_sim" / "api")
    for d in dirs:
        if (d / LIB_NAME).is_file():
            return d / LIB_NAME
    raise FileNotFoundError(
        f"{LIB_NAME} not found in {[str(d) for d in dirs]}: build the host-iq preset "
        "(cmake --preset host-iq && cmake --build --preset host-iq), or set IMFOC_LIB_DIR to a "
        "build directory or IMFOC_LIB to the library file")


_lib = None


def load():
    """The loaded library with its prototypes (loaded once)."""
    global _lib
    if _lib is not None:
        return _lib
    lib = C.CDLL(str(find_library()))
    P = C.c_void_p
    i32 = C.c_int32
    proto = {
        "imfoc_api_version": (i32, []),
        "imfoc_publish_reason_str": (C.c_char_p, [i32]),
        "imfoc_status_str": (C.c_char_p, [i32]),
        "imfoc_create_ini": (P, [C.c_char_p, C.c_char_p, C.c_size_t]),
        "imfoc_destroy": (None, [P]),
        "imfoc_get_info": (i32, [P, C.POINTER(Info)]),
        "imfoc_set_background_div": (i32, [P, C.c_uint16]),
        "imfoc_background": (i32, [P]),
        "imfoc_command": (i32, [P, i32]),
        "imfoc_set_speed_rpm": (i32, [P, C.c_double]),
        "imfoc_step_raw": (i32, [P, C.POINTER(RawIn), C.POINTER(Out)]),
        "imfoc_step_phys": (i32, [P, C.POINTER(PhysIn), C.POINTER(Out)]),
        "imfoc_phys_to_raw": (i32, [P, C.POINTER(PhysIn), C.POINTER(RawIn)]),
        "imfoc_get_signals": (i32, [P, C.POINTER(Signals)]),
    }
    for name, (res, args) in proto.items():
        fn = getattr(lib, name)
        fn.restype = res
        fn.argtypes = args
    v = lib.imfoc_api_version()
    if v != API_VERSION:
        raise RuntimeError(f"{find_library()}: API version {v}, this package needs {API_VERSION}")
    _lib = lib
    return lib
