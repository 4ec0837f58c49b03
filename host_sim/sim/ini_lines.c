/* The INI line reader.  See ini_lines.h. */
#include "ini_lines.h"

#include <errno.h>
#include <string.h>

/* What inih would accept but a file of ours never means: NULL if the line is
 * blank, a comment, `[section]` (then nothing but a comment) or
 * `key = value` with no ':' before the '=' (inih's other delimiter). */
static const char *syntax_error(const char *line)
{
    const char *p = line + strspn(line, " \t\r");
    if (*p == '\0' || *p == ';' || *p == '#') {
        return NULL;
    }
    if (*p == '[') {
        const char *e = strchr(p, ']');
        if (e == NULL) {
            return "section header without its ']'";
        }
        e += 1 + strspn(e + 1, " \t\r");
        return (*e == '\0' || *e == ';' || *e == '#') ? NULL
                                                    : "text after the section header's ']'";
    }
    {
        const char *eq = strchr(p, '=');
        const char *colon = strchr(p, ':');
        if (colon != NULL && (eq == NULL || colon < eq)) {
            return "key and value separated by ':' (write key = value)";
        }
    }
    return NULL;
}

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
    str[n] = '\0';
    r->syntax = syntax_error(str);
    if (r->syntax != NULL) {
        r->line++;
        r->status = RD_SYNTAX;
        return NULL;
    }
    r->line++;
    return str;
}
