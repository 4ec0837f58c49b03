/**
 * @file fuzz_target.h
 * The libFuzzer entry point that each fuzz target defines.  The same object
 * links either with libFuzzer (-fsanitize=fuzzer, clang: tools/fuzz.sh) or
 * with fuzz_replay_main.c, which feeds it the committed corpus files as a
 * plain CTest test in every build (gcc, FLOAT_MATH, ASan+UBSan).
 */
#ifndef FUZZ_TARGET_H
#define FUZZ_TARGET_H

#include <stddef.h>
#include <stdint.h>

/** Run one input.  Returns 0; a violated property aborts (fuzz_fail). */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/** After a replay of the committed corpus: print what it covered and return
 *  non-zero if it no longer covers what it must (e.g. every state of the
 *  identification sequence), so that a stale corpus is noticed. */
int fuzz_corpus_check(void);

/** Report a violated property and abort, so that libFuzzer saves the input
 *  and the replay test fails. */
void fuzz_fail(const char *what, unsigned long step, long value, long limit);

#endif /* FUZZ_TARGET_H */
