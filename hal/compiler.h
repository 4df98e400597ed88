/* compiler.h: SDCC storage keywords on the 8051, mapped away for the host build (as SDCC's testfwk.h does). */
#ifndef SPRAYER_COMPILER_H
#define SPRAYER_COMPILER_H

#ifdef __SDCC
/* SDCC's own compiler.h (SFR/SBIT macros) sits behind this one on the include path. */
#include_next <compiler.h>
#define FX_CODE __code
#define FX_DATA __data
#define FX_XDATA __xdata
#else
#define __code
#define __data
#define __idata
#define __pdata
#define __xdata
#define __near
#define __far
#define __reentrant
#define __critical
#define __at(x)
#define __interrupt(n)
#define __using(n)
#define __bit uint8_t
#define FX_CODE
#define FX_DATA
#define FX_XDATA
#endif

#include <stdint.h>

/* FW_PEERS: the peers' controllers (aog, raven), baselines to compare with, are in every build
 * but the chip's field image (and PIL, which runs that image in s51), which keeps its flash for
 * the sprayer's own work; `make firmware FW_PEERS=1` builds the chip's comparison image. */
#ifndef FW_PEERS
#if defined(HAL_STC12) || defined(HAL_PIL)
#define FW_PEERS 0
#else
#define FW_PEERS 1
#endif
#endif

/* FW_PGN: AgOpenGPS and RateControl frames on the serial link (firmware/link/pgn.h), Remote's
 * value 3: in every build but the chip's bench (HIL=1) and research (FW_PEERS=1) images, which
 * have no room for them (docs/MEMORY.md). Their settings are in every image's table (params.h),
 * used only with the frames. */
#ifndef FW_PGN
#if defined(HAL_STC12)
#define FW_PGN (!FW_HIL && !FW_PEERS)
#else
#define FW_PGN 1
#endif
#endif

/* FW_IOTEST: the console's I/O test (console_io.c), the wiring checked at bring-up on the
 * bench: in the bench image (HIL=1), the host's, the s51 tests' and PIL's builds; not in the
 * field image nor the research image, whose flash goes to the sprayer's own work (docs/MEMORY.md). */
#ifndef FW_IOTEST
#if defined(HAL_STC12)
#define FW_IOTEST FW_HIL
#else
#define FW_IOTEST 1
#endif
#endif

/* FW_PROBES: accessors only the host's programs, the s51 tests and PIL read (a flag, a learnt
 * byte, a gain, a synchronous save): not in the chip's image, where nothing calls them. */
#ifndef FW_PROBES
#if defined(HAL_STC12)
#define FW_PROBES 0
#else
#define FW_PROBES 1
#endif
#endif

#endif
