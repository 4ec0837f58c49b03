/**
 * @file pie.h
 * The peripheral interrupt expansion (PIE) block and its vector table
 * (SPRU078 "PIE").
 */
#ifndef PIE_H
#define PIE_H

/** Disable and clear every CPU and PIE interrupt, fill the whole PIE vector
 *  table with a trap, then enable the PIE (ENPIE = 1).  The application then
 *  installs its own vectors (isr_install). */
void pie_init(void);

#endif /* PIE_H */
