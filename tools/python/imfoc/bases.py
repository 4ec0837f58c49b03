"""Per-unit bases of the drive, from the INI file the firmware was built from, computed as
src/common/base_values.c does (include/base_values.h):

    I_base = current-sensor full scale          V_base = V_dc,nominal / sqrt(3)
    f_base = rated frequency, w_base = 2 pi f_base, t_base = 1 / w_base
    Z_base = V_base / I_base, L_base = Z_base / w_base, psi_base = V_base / w_base
    n_base = 60 f_base / pole_pairs (mechanical r/min of 1 pu electrical speed)

The keys the numbers come from are in INI_KEYS only: the INI layout may change, and then
only that table does.
"""
import configparser
import math
from dataclasses import dataclass

# quantity -> (section, key, default or None if required), as host_sim/sim/sim_config.c
# names them and sim_config_to_drive() hands them to drive_init (the drive side of the
# INI: the bases are the firmware's, board.vdc_nominal_V not the simulated bus)
INI_KEYS = {
    "current_full_scale_A": ("board", "current_full_scale_A", None),
    "vdc_nominal_V": ("board", "vdc_nominal_V", None),
    "rated_freq_Hz": ("nameplate", "rated_freq_Hz", None),
    "pole_pairs": ("nameplate", "pole_pairs", None),
    # the telemetry's rate (a burst every 750 ISRs): the drive's clock on the PC
    "pwm_freq_Hz": ("board", "pwm_freq_Hz", 15000),
    # the identification sequence, to know when the published set is this run's final one
    "passes": ("ident", "passes", 1),
    "track_rr": ("ident", "track_rr", 0),
}


class ConfigError(ValueError):
    pass


def read_ini(path):
    """The INI file as the simulator reads it (';' and '#' comments, keys case-kept);
    ConfigError naming the file if it cannot be read."""
    cp = configparser.ConfigParser(inline_comment_prefixes=(";", "#"),
                                   comment_prefixes=(";", "#"), strict=False)
    cp.optionxform = str
    try:
        with open(path, encoding="utf-8") as f:
            cp.read_file(f)
    except (OSError, UnicodeDecodeError, configparser.Error) as e:
        raise ConfigError(f"{path}: cannot read ({e.__class__.__name__}: {e})") from None
    return cp


def read_ini_values(path, keys=None):
    """The quantities of `keys` (default INI_KEYS: name -> (section, key, default or None
    if required)) in the file as floats; ConfigError naming the file and the key if a
    required one is missing or not a number."""
    cp = read_ini(path)
    out = {}
    for name, (sec, key, default) in (INI_KEYS if keys is None else keys).items():
        if not cp.has_option(sec, key):
            if default is None:
                raise ConfigError(f"{path}: missing [{sec}] {key}")
            out[name] = float(default)
            continue
        try:
            v = float(cp.get(sec, key))
        except ValueError:
            raise ConfigError(f"{path}: [{sec}] {key} is not a number") from None
        if not math.isfinite(v):
            raise ConfigError(f"{path}: [{sec}] {key} is not finite")
        out[name] = v
    return out


@dataclass(frozen=True)
class Bases:
    I_base_A: float
    V_base_V: float
    f_base_Hz: float
    pole_pairs: int
    passes: int = 1
    track_rr: int = 0
    pwm_freq_Hz: float = 15000.0

    @property
    def w_base_rad_s(self):
        return 2.0 * math.pi * self.f_base_Hz

    @property
    def t_base_s(self):
        return 1.0 / self.w_base_rad_s

    @property
    def Z_base_ohm(self):
        return self.V_base_V / self.I_base_A

    @property
    def L_base_H(self):
        return self.Z_base_ohm / self.w_base_rad_s

    @property
    def psi_base_Wb(self):
        return self.V_base_V / self.w_base_rad_s

    @property
    def n_base_rpm(self):
        return 60.0 * self.f_base_Hz / self.pole_pairs

    @classmethod
    def from_ini(cls, path):
        v = read_ini_values(path)
        if not (v["current_full_scale_A"] > 0 and v["vdc_nominal_V"] > 0
                and v["rated_freq_Hz"] > 0 and v["pole_pairs"] >= 1 and v["pwm_freq_Hz"] > 0):
            raise ConfigError(f"{path}: the current full scale, bus voltage, rated frequency, "
                              "pole pairs and PWM frequency must be positive")
        return cls(I_base_A=v["current_full_scale_A"], V_base_V=v["vdc_nominal_V"] / math.sqrt(3),
                   f_base_Hz=v["rated_freq_Hz"], pole_pairs=int(v["pole_pairs"]),
                   passes=int(v["passes"]), track_rr=int(v["track_rr"]),
                   pwm_freq_Hz=v["pwm_freq_Hz"])

    def si(self, name, pu):
        """A Q24 telemetry field (firmware/telemetry.h) in SI: (column name, value)."""
        col, base = SI_FIELDS[name]
        return col, pu * getattr(self, base)


# Q24 telemetry field -> (SI column name, the base it is per unit of)
SI_FIELDS = {
    "speed": ("speed_rpm", "n_base_rpm"),          # electrical pu = mechanical pu
    "speed_ref": ("speed_ref_rpm", "n_base_rpm"),
    "i_m": ("i_m_A", "I_base_A"),
    "i_t": ("i_t_A", "I_base_A"),
    "vdc": ("vdc_V", "V_base_V"),
    "Rs": ("Rs_ohm", "Z_base_ohm"),
    "Rr": ("Rr_ohm", "Z_base_ohm"),
    "Lm": ("Lm_H", "L_base_H"),
    "Lr": ("Lr_H", "L_base_H"),
    "psi_r": ("psi_r_Wb", "psi_base_Wb"),
    "Tr": ("Tr_s", "t_base_s"),
    "Rs_dc": ("Rs_dc_ohm", "Z_base_ohm"),
    "sigma_ls_dc": ("sigma_ls_dc_H", "L_base_H"),
    "Rr_track": ("Rr_track_ohm", "Z_base_ohm"),
    "Tr_track": ("Tr_track_s", "t_base_s"),
}
# the published set, in the order of the paper's Table 1 and of report.json
PARAM_FIELDS = ("Rs", "Rr", "Lm", "Lr", "psi_r", "Tr")
