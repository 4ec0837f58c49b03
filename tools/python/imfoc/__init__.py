"""imfoc: run the im-rls-foc firmware (fixed-point F2812 induction-motor FOC with
online RLS identification) against plants written in Python.

    from imfoc import Drive, InductionMotor
    d = Drive("host_sim/config/paper_motor.ini")

See imfoc.example for a closed loop with a numpy motor model.
"""
from ._lib import find_library, PARAM_NAMES, REPO_ROOT
from .drive import (Drive, ImfocError, read_ini, write_config, CONFIG_DIR, STATES,
                    CMD_START_IDENT, CMD_STOP, CMD_RESET_FAULT, CMD_SELECT_STANDSTILL,
                    CMD_SELECT_ROTATING)
from .plant import InductionMotor, MotorParams
from .protocol import REASONS, FAULTS

__all__ = ["Drive", "ImfocError", "InductionMotor", "MotorParams", "read_ini", "write_config",
           "find_library", "CONFIG_DIR", "REPO_ROOT", "STATES", "PARAM_NAMES",
           "CMD_START_IDENT", "CMD_STOP", "CMD_RESET_FAULT", "CMD_SELECT_STANDSTILL",
           "CMD_SELECT_ROTATING", "REASONS", "FAULTS"]
