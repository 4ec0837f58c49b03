/* The INI line reader.  See ini_lines.h. */
#include "ini_lines.h"

#include <errno.h>

char *ini_read_line(char *str, int num, void *stream)
{
    line_reader_t *r = (line_reader_t *)stream;
    int n = 0, c = 0;

    if (r->status != RD_OK || num < 2) {
        return NULL;
    }
    r->max_len = num - 1;
    while (n < num - 1) {
        c = getc(r->f);
        if (c == EOF || c == '\n') {
            break;
        }
        if (c == '\0') {
            r->status = RD_NUL;
            return NULL;
        }
        str[n++] = (char)c;
    }
    if (n == num - 1 && c != '\n' && c != EOF) {
        /* the buffer is full: the line must end right here */
        c = getc(r->f);
        if (c != '\n' && c != EOF) {
            r->line++;
            r->status = RD_TOO_LONG;
            return NULL;
        }
    }
    if (c == EOF && ferror(r->f)) {
        r->err_no = errno;
        r->status = RD_ERROR;
        return NULL;
    }
    if (c == EOF && n == 0) {
        return NULL;    /* end of file */
    }
    r->line++;
    str[n] = '\0';
    return str;
}
