/*
 * Host nanoseconds per frame build and parse with generated/c/regmap_rtu.h (`make bench`,
 * bench/chelpers.py). Prints one line per case: its name, then the ns per operation of each of
 * REPEATS timed loops; Python takes the median. Inputs change every iteration and an empty asm
 * statement with a memory clobber stops the compiler from hoisting work out of the loops.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "regmap_rtu.h"

#define REPEATS 7
#define BARRIER() __asm__ __volatile__("" ::: "memory")

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static unsigned long sink;

static size_t read_response(uint8_t *frame, uint16_t count)
{
    uint16_t i;
    frame[0] = 1u;
    frame[1] = REGMAP_FC_READ_HOLDING;
    frame[2] = (uint8_t)(2u * count);
    for (i = 0u; i < count; ++i) {
        regmap_put_be16(&frame[3u + 2u * i], (uint16_t)(i * 2654435761u));
    }
    return regmap_rtu_finish(frame, REGMAP_RTU_MAX_FRAME, 3u + 2u * (size_t)count);
}

static void case_build_read(long n)
{
    uint8_t buf[REGMAP_RTU_MAX_FRAME];
    int r;
    printf("build_read");
    for (r = 0; r < REPEATS; ++r) {
        long i;
        double start = now_ns();
        for (i = 0; i < n; ++i) {
            sink += regmap_rtu_build_read(buf, sizeof buf, 1u, (uint16_t)(i & 0x7FFF), (uint16_t)(1 + (i & 63)));
            sink += buf[6];
            BARRIER();
        }
        printf(" %.2f", (now_ns() - start) / (double)n);
    }
    printf("\n");
}

static void case_build_write_multiple(long n)
{
    uint8_t buf[REGMAP_RTU_MAX_FRAME];
    uint16_t words[10] = { 1, 2, 3, 4, 5, 6, 7, 8, 9, 10 };
    int r;
    printf("build_write_multiple_10");
    for (r = 0; r < REPEATS; ++r) {
        long i;
        double start = now_ns();
        for (i = 0; i < n; ++i) {
            words[0] = (uint16_t)i;
            sink += regmap_rtu_build_write_multiple(buf, sizeof buf, 1u, (uint16_t)(i & 0x7FFF), words, 10u);
            sink += buf[25];
            BARRIER();
        }
        printf(" %.2f", (now_ns() - start) / (double)n);
    }
    printf("\n");
}

static void case_parse_read(long n, uint16_t count)
{
    uint8_t frame[REGMAP_RTU_MAX_FRAME];
    uint16_t words[REGMAP_RTU_MAX_READ_REGISTERS];
    size_t len = read_response(frame, count);
    uint8_t exc = 0u;
    int r;
    printf("parse_read_%u", (unsigned)count);
    for (r = 0; r < REPEATS; ++r) {
        long i;
        double start = now_ns();
        for (i = 0; i < n; ++i) {
            regmap_status status = regmap_rtu_parse_read_response(frame, len, 1u, count, words, REGMAP_RTU_MAX_READ_REGISTERS, &exc);
            if (status != REGMAP_OK) {
                fprintf(stderr, "parse failed: %d\n", (int)status);
                exit(1);
            }
            sink += words[count - 1u];
            BARRIER();
        }
        printf(" %.2f", (now_ns() - start) / (double)n);
    }
    printf("\n");
}

int main(int argc, char **argv)
{
    long n = argc > 1 ? atol(argv[1]) : 200000L;
    case_build_read(n);
    case_build_write_multiple(n);
    case_parse_read(n, 1u);
    case_parse_read(n / 10 > 0 ? n / 10 : 1, 100u);
    fprintf(stderr, "sink %lu\n", sink);
    return 0;
}
