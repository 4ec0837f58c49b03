/*
 * Host-side shim of TI's DSP281x_Device.h (SPRC097, DSP281x header files
 * v1.00+), used ONLY by the CI check `target_fw_syntax_*` (tests/target/):
 * the firmware is compiled with host gcc -fsyntax-only against these
 * declarations, so a register or field name that is not TI's fails CI.
 *
 * Written from TI's documentation (SPRU065 EV, SPRU060 ADC, SPRU078 system
 * control and interrupts, SPRU051 SCI) and the names of the DSP281x header
 * files.  Only the registers the firmware uses are declared, but each with
 * its complete TI bit-field list, in TI's order, with TI's reserved words,
 * so that the layout matches the silicon.  It is NOT the target build's
 * header: the target build uses TI's own DSP281x_headers (see
 * cmake/toolchain-ti-c2000.cmake).
 *
 * The C28x keywords are shimmed: `interrupt` and `cregister` expand to
 * nothing, the EALLOW/EDIS/EINT/DINT/ERTM macros to compiler barriers.
 * `#pragma CODE_SECTION/DATA_SECTION` are accepted by building with
 * -Wno-unknown-pragmas.
 */
#ifndef DSP281x_DEVICE_H
#define DSP281x_DEVICE_H

#include <stdint.h>

#define TARGET 1
#define DSP28_F2812 TARGET

/* C28x keywords and intrinsic asm macros (DSP281x_Device.h) */
#define interrupt
#define cregister
#define EINT   __asm__ __volatile__("" ::: "memory")
#define DINT   __asm__ __volatile__("" ::: "memory")
#define ERTM   __asm__ __volatile__("" ::: "memory")
#define DRTM   __asm__ __volatile__("" ::: "memory")
#define EALLOW __asm__ __volatile__("" ::: "memory")
#define EDIS   __asm__ __volatile__("" ::: "memory")
#define ESTOP0 __asm__ __volatile__("" ::: "memory")

/* CPU interrupt enable masks for IER (DSP281x_Device.h) */
#define M_INT1  0x0001
#define M_INT2  0x0002
#define M_INT3  0x0004
#define M_INT4  0x0008
#define M_INT5  0x0010
#define M_INT6  0x0020
#define M_INT7  0x0040
#define M_INT8  0x0080
#define M_INT9  0x0100
#define M_INT10 0x0200
#define M_INT11 0x0400
#define M_INT12 0x0800
#define M_INT13 0x1000
#define M_INT14 0x2000

/* TI's types (16-bit int on C28x: Uint16 is unsigned int there) */
typedef int16_t  int16;
typedef int32_t  int32;
typedef uint16_t Uint16;
typedef uint32_t Uint32;
typedef float    float32;

/* Core registers (cregister on C28x) */
extern cregister volatile Uint16 IFR;
extern cregister volatile Uint16 IER;

#include "DSP281x_Adc.h"
#include "DSP281x_Ev.h"
#include "DSP281x_Gpio.h"
#include "DSP281x_PieCtrl.h"
#include "DSP281x_PieVect.h"
#include "DSP281x_Sci.h"
#include "DSP281x_SysCtrl.h"

#endif /* DSP281x_DEVICE_H */
