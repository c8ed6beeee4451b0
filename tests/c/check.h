/* Minimal test harness: CHECK(cond, fmt, ...) records a failure; main returns check_report(). */
#ifndef FPL_TEST_CHECK_H
#define FPL_TEST_CHECK_H
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static int check_failures = 0, check_count = 0;

#define CHECK(cond, ...)                                                                       \
    do {                                                                                       \
        check_count++;                                                                         \
        if (!(cond)) {                                                                         \
            check_failures++;                                                                  \
            fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);            \
            fprintf(stderr, __VA_ARGS__);                                                      \
            fprintf(stderr, "\n");                                                             \
        }                                                                                      \
    } while (0)

#define CHECK_OK(call)                                                                         \
    do {                                                                                       \
        int st_ = (call);                                                                      \
        CHECK(st_ == 0, "%s returned %d: %s", #call, st_, fpl_last_error());                   \
    } while (0)

static int check_report(const char *name)
{
    printf("%s: %d checks, %d failed\n", name, check_count, check_failures);
    return check_failures ? EXIT_FAILURE : EXIT_SUCCESS;
}

/* Deterministic pseudo-random numbers in [-1, 1) for test inputs (independent of the library). */
static unsigned long long check_rng_state = 88172645463325252ULL;
static inline double check_uniform(void)
{
    check_rng_state ^= check_rng_state << 13;
    check_rng_state ^= check_rng_state >> 7;
    check_rng_state ^= check_rng_state << 17;
    return (double)(check_rng_state >> 11) / 4503599627370496.0 - 1.0;
}
#if defined(_POSIX_C_SOURCE) && _POSIX_C_SOURCE >= 200809L
#include <unistd.h>
/* Capture what the code under test writes on stdout/stderr (the library must never print):
 * begin redirects both to a temporary file, end restores them and returns the bytes written
 * (the first line in head). A test file that wants it defines _POSIX_C_SOURCE 200809L first. */
typedef struct check_capture {
    FILE *file;
    int out, err;
} check_capture;

static inline int check_capture_begin(check_capture *c)
{
    fflush(stdout);
    fflush(stderr);
    c->file = tmpfile();
    if (!c->file) return -1;
    c->out = dup(1);
    c->err = dup(2);
    dup2(fileno(c->file), 1);
    dup2(fileno(c->file), 2);
    return 0;
}

static inline long check_capture_end(check_capture *c, char *head, int size)
{
    fflush(stdout);
    fflush(stderr);
    dup2(c->out, 1);
    dup2(c->err, 2);
    close(c->out);
    close(c->err);
    fseek(c->file, 0, SEEK_END);
    long printed = ftell(c->file);
    head[0] = '\0';
    rewind(c->file);
    if (printed > 0 && !fgets(head, size, c->file)) head[0] = '\0';
    fclose(c->file);
    return printed;
}
#endif
#endif
