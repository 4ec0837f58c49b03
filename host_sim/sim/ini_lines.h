/* The line reader for inih (ini_parse_stream) of the simulator's INI files.
 * inih's own reader is fgets into a buffer of INI_MAX_LINE characters: it
 * splits a longer line and parses the rest as a line of its own (the tail of
 * a long comment could become a key), a NUL byte silently ends a line, and a
 * read error (a directory given as the file) looks like an empty file; and it
 * reads `[board` (no `]`), `[board] x` (text after the `]`) and `key : value`
 * (its other delimiter) without a word.  This reader stops at each of these
 * and says which, so that sim_config_load reports it. */
#ifndef INI_LINES_H
#define INI_LINES_H

#include <stdio.h>

typedef enum { RD_OK = 0, RD_TOO_LONG, RD_NUL, RD_ERROR, RD_SYNTAX } read_status_t;

typedef struct {
    FILE *f;
    unsigned line;          /* lines handed to inih so far */
    int max_len;            /* longest line inih accepts, characters */
    read_status_t status;
    int err_no;             /* errno of a read error */
    const char *syntax;     /* RD_SYNTAX: what is wrong with the line (a constant text) */
} line_reader_t;

/** inih's ini_reader: @p stream is a line_reader_t with f open. */
char *ini_read_line(char *str, int num, void *stream);

#endif /* INI_LINES_H */
