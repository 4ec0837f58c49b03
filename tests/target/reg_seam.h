/* A link-time seam for one firmware file's register accesses (tests/target
 * only; the firmware itself is unchanged).  Force-included (-include) before
 * the firmware source: the shim's declarations are read first, then every
 * later `EvaRegs` / `SysCtrlRegs` / `GpioDataRegs` of that file becomes a
 * call of the test's reg_seam_eva() / _sysctrl() / _gpio_data(), which
 * returns the fake register block
 * and can act as the hardware does between two accesses (a PDPINTA edge, a
 * log of the values written).  One call per access of the source: a
 * read-modify-write statement (`EvaRegs.COMCONA.bit.FCOMPOE = 1u`) is one
 * access, its read and its write not separable here. */
#ifndef REG_SEAM_H
#define REG_SEAM_H

#include "DSP281x_Device.h"

volatile struct EVA_REGS *reg_seam_eva(void);
volatile struct SYS_CTRL_REGS *reg_seam_sysctrl(void);
volatile struct GPIO_DATA_REGS *reg_seam_gpio_data(void);

/* the test itself defines the functions: it includes this file with
 * REG_SEAM_NO_MACROS and keeps the register names for its own use */
#ifndef REG_SEAM_NO_MACROS
#define EvaRegs (*reg_seam_eva())
#define SysCtrlRegs (*reg_seam_sysctrl())
#define GpioDataRegs (*reg_seam_gpio_data())
#endif

#endif /* REG_SEAM_H */
