/*
 * Replay driver: runs a fuzz target on files, without libFuzzer, so that the
 * committed corpus (and every crash input added to it) is a regression test
 * in every build, gcc included.
 *
 *   fuzz_X_replay PATH...     PATH: a file, or a directory of files
 *
 * Exit status 0 when every input ran and fuzz_corpus_check() is satisfied;
 * a violated property aborts inside the target.
 */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fuzz_target.h"

#define REPLAY_MAX_INPUT (1u << 20)

static unsigned char g_buf[REPLAY_MAX_INPUT];

static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    size_t n;
    if (f == NULL) {
        fprintf(stderr, "fuzz replay: cannot open %s\n", path);
        return 1;
    }
    n = fread(g_buf, 1, sizeof g_buf, f);
    fclose(f);
    if (n == sizeof g_buf) {
        fprintf(stderr, "fuzz replay: %s is larger than %u bytes\n", path, REPLAY_MAX_INPUT);
        return 1;
    }
    (void)LLVMFuzzerTestOneInput(g_buf, n);
    return 0;
}

/* Files of one directory in name order (readdir's order is arbitrary). */
static int cmp_names(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

static int run_dir(const char *dir, unsigned *count)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    char *names[1024];
    size_t n = 0, i;
    int bad = 0;
    if (d == NULL) {
        fprintf(stderr, "fuzz replay: cannot open directory %s\n", dir);
        return 1;
    }
    while ((e = readdir(d)) != NULL && n < sizeof names / sizeof names[0]) {
        char path[4096];
        struct stat st;
        if (e->d_name[0] == '.') {
            continue;
        }
        if ((size_t)snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= sizeof path ||
            stat(path, &st) != 0 || !S_ISREG(st.st_mode)) {
            continue;
        }
        names[n] = strdup(path);
        if (names[n] == NULL) {
            bad = 1;
            break;
        }
        n++;
    }
    closedir(d);
    qsort(names, n, sizeof names[0], cmp_names);
    for (i = 0; i < n; i++) {
        if (bad == 0) {
            bad = run_file(names[i]);
            (*count)++;
        }
        free(names[i]);
    }
    return bad;
}

int main(int argc, char **argv)
{
    unsigned count = 0;
    int i;
    for (i = 1; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            fprintf(stderr, "fuzz replay: no such file or directory: %s\n", argv[i]);
            return 1;
        }
        if (S_ISDIR(st.st_mode) ? run_dir(argv[i], &count) != 0 : run_file(argv[i]) != 0) {
            return 1;
        }
        if (!S_ISDIR(st.st_mode)) {
            count++;
        }
    }
    if (count == 0u) {
        fprintf(stderr, "fuzz replay: no inputs\n");
        return 1;
    }
    printf("fuzz replay: %u inputs\n", count);
    return fuzz_corpus_check() != 0 ? 1 : 0;
}
