/**
 * @file report.h
 * The run's results as DIR/report.json and as a table like the paper's
 * Table 1 (reference, identified, error %).
 */
#ifndef REPORT_H
#define REPORT_H

#include <stdio.h>
#include "sim_run.h"

/** Write report.json; returns 0 or -1 if the file cannot be written. */
int report_write_json(const char *path, const sim_config_t *cfg, const char *config_path,
                      const sim_options_t *opt, const sim_result_t *r);
/** Print the Table-1-like comparison and the run figures. */
void report_print_table(FILE *f, const sim_result_t *r);
/** Print the passes, the standstill Rs and the drift window's figures, where
 *  the run has them (nothing for the paper's sequence). */
void report_print_adaptation(FILE *f, const sim_result_t *r);

#endif /* REPORT_H */
