/*
 * Code size of the RTU frame helpers and the CRC on a Cortex-M0 (`make bench`, bench/chelpers.py).
 * Each static inline helper of generated/c/regmap_rtu.h gets one out-of-line wrapper, so the object
 * holds what a firmware calling all of them links. -DBENCH_READ_ONLY keeps only what a master that
 * just reads needs: build a read request, check and parse its answer.
 */
#include "regmap_rtu.h"

size_t bench_build_read(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t count);
regmap_status bench_parse_read(const uint8_t *frame, size_t len, uint8_t slave, uint16_t count, uint16_t *words, size_t cap,
                               uint8_t *exc);
size_t bench_response_len(const uint8_t *frame, size_t have);

size_t bench_build_read(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t count)
{
    return regmap_rtu_build_read(buf, cap, slave, address, count);
}

regmap_status bench_parse_read(const uint8_t *frame, size_t len, uint8_t slave, uint16_t count, uint16_t *words, size_t cap,
                               uint8_t *exc)
{
    return regmap_rtu_parse_read_response(frame, len, slave, count, words, cap, exc);
}

size_t bench_response_len(const uint8_t *frame, size_t have)
{
    return regmap_rtu_response_len(frame, have);
}

#ifndef BENCH_READ_ONLY
uint16_t bench_crc16(const uint8_t *data, size_t len);
bool bench_crc_ok(const uint8_t *frame, size_t len);
size_t bench_build_write_single(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t value);
size_t bench_build_write_multiple(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, const uint16_t *words, uint16_t count);
regmap_status bench_parse_write_single(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, uint16_t value, uint8_t *exc);
regmap_status bench_parse_write_multiple(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, uint16_t count, uint8_t *exc);

uint16_t bench_crc16(const uint8_t *data, size_t len)
{
    return regmap_crc16(data, len);
}

bool bench_crc_ok(const uint8_t *frame, size_t len)
{
    return regmap_rtu_crc_ok(frame, len);
}

size_t bench_build_write_single(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t value)
{
    return regmap_rtu_build_write_single(buf, cap, slave, address, value);
}

size_t bench_build_write_multiple(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, const uint16_t *words, uint16_t count)
{
    return regmap_rtu_build_write_multiple(buf, cap, slave, address, words, count);
}

regmap_status bench_parse_write_single(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, uint16_t value, uint8_t *exc)
{
    return regmap_rtu_parse_write_single_response(frame, len, slave, address, value, exc);
}

regmap_status bench_parse_write_multiple(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, uint16_t count, uint8_t *exc)
{
    return regmap_rtu_parse_write_multiple_response(frame, len, slave, address, count, exc);
}
#endif
