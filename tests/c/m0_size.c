/*
 * Code size of the RTU frame helpers on a Cortex-M0: out-of-line wrappers make the compiler emit
 * each static inline helper once, as a firmware using all of them would. Compiled with
 * arm-none-eabi-gcc -mcpu=cortex-m0 -mthumb -Os -c and measured with arm-none-eabi-size
 * (tests/backends/c/test_c_backend.py). REGMAP_SIZE_WITH_WORDS adds the 16/32-bit word conversions;
 * REGMAP_SIZE_WITH_SPACES the coil, discrete-input and input-register frames, bit packing, a float
 * in any order and the string copy (issue 19).
 */
#include "regmap_rtu.h"

size_t m0_build_read(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t count);
size_t m0_build_write_single(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t value);
size_t m0_build_write_multiple(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, const uint16_t *words, uint16_t count);
regmap_status m0_parse_read(const uint8_t *frame, size_t len, uint8_t slave, uint16_t count, uint16_t *words, size_t cap, uint8_t *exc);
regmap_status m0_parse_write_single(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, uint16_t value, uint8_t *exc);
regmap_status m0_parse_write_multiple(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, uint16_t count, uint8_t *exc);
size_t m0_response_len(const uint8_t *frame, size_t have);

size_t m0_build_read(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t count)
{
    return regmap_rtu_build_read(buf, cap, slave, address, count);
}

size_t m0_build_write_single(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t value)
{
    return regmap_rtu_build_write_single(buf, cap, slave, address, value);
}

size_t m0_build_write_multiple(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, const uint16_t *words, uint16_t count)
{
    return regmap_rtu_build_write_multiple(buf, cap, slave, address, words, count);
}

regmap_status m0_parse_read(const uint8_t *frame, size_t len, uint8_t slave, uint16_t count, uint16_t *words, size_t cap, uint8_t *exc)
{
    return regmap_rtu_parse_read_response(frame, len, slave, count, words, cap, exc);
}

regmap_status m0_parse_write_single(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, uint16_t value, uint8_t *exc)
{
    return regmap_rtu_parse_write_single_response(frame, len, slave, address, value, exc);
}

regmap_status m0_parse_write_multiple(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, uint16_t count, uint8_t *exc)
{
    return regmap_rtu_parse_write_multiple_response(frame, len, slave, address, count, exc);
}

size_t m0_response_len(const uint8_t *frame, size_t have)
{
    return regmap_rtu_response_len(frame, have);
}

#ifdef REGMAP_SIZE_WITH_WORDS
int32_t m0_s32(const uint16_t *words, regmap_word_order order);
void m0_to_words(int32_t value, regmap_word_order order, uint16_t *words);
int16_t m0_s16(uint16_t word);

int32_t m0_s32(const uint16_t *words, regmap_word_order order)
{
    return regmap_s32_from_words(words, order);
}

void m0_to_words(int32_t value, regmap_word_order order, uint16_t *words)
{
    regmap_s32_to_words(value, order, words);
}

int16_t m0_s16(uint16_t word)
{
    return regmap_s16_from_word(word);
}
#endif

#ifdef REGMAP_SIZE_WITH_SPACES
size_t m0_build_read_coils(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t count);
size_t m0_build_read_discrete_inputs(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t count);
size_t m0_build_read_input_registers(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t count);
size_t m0_build_write_single_coil(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, bool on);
size_t m0_build_write_multiple_coils(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, const bool *bits, uint16_t count);
regmap_status m0_parse_coils(const uint8_t *frame, size_t len, uint8_t slave, uint16_t count, bool *bits, size_t cap, uint8_t *exc);
regmap_status m0_parse_discrete_inputs(const uint8_t *frame, size_t len, uint8_t slave, uint16_t count, bool *bits, size_t cap, uint8_t *exc);
regmap_status m0_parse_input(const uint8_t *frame, size_t len, uint8_t slave, uint16_t count, uint16_t *words, size_t cap, uint8_t *exc);
regmap_status m0_parse_write_single_coil(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, bool on, uint8_t *exc);
regmap_status m0_parse_write_multiple_coils(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, uint16_t count, uint8_t *exc);
float m0_f32(const uint16_t *words, regmap_word_order word_order, regmap_byte_order byte_order);
size_t m0_text(const uint16_t *words, size_t count, regmap_byte_order byte_order, regmap_padding padding, char *text, size_t size);

size_t m0_build_read_coils(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t count)
{
    return regmap_rtu_build_read_coils(buf, cap, slave, address, count);
}

size_t m0_build_read_discrete_inputs(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t count)
{
    return regmap_rtu_build_read_discrete_inputs(buf, cap, slave, address, count);
}

size_t m0_build_read_input_registers(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, uint16_t count)
{
    return regmap_rtu_build_read_input_registers(buf, cap, slave, address, count);
}

size_t m0_build_write_single_coil(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, bool on)
{
    return regmap_rtu_build_write_single_coil(buf, cap, slave, address, on);
}

size_t m0_build_write_multiple_coils(uint8_t *buf, size_t cap, uint8_t slave, uint16_t address, const bool *bits, uint16_t count)
{
    return regmap_rtu_build_write_multiple_coils(buf, cap, slave, address, bits, count);
}

regmap_status m0_parse_coils(const uint8_t *frame, size_t len, uint8_t slave, uint16_t count, bool *bits, size_t cap, uint8_t *exc)
{
    return regmap_rtu_parse_read_coils_response(frame, len, slave, count, bits, cap, exc);
}

regmap_status m0_parse_discrete_inputs(const uint8_t *frame, size_t len, uint8_t slave, uint16_t count, bool *bits, size_t cap, uint8_t *exc)
{
    return regmap_rtu_parse_read_discrete_inputs_response(frame, len, slave, count, bits, cap, exc);
}

regmap_status m0_parse_input(const uint8_t *frame, size_t len, uint8_t slave, uint16_t count, uint16_t *words, size_t cap, uint8_t *exc)
{
    return regmap_rtu_parse_read_input_response(frame, len, slave, count, words, cap, exc);
}

regmap_status m0_parse_write_single_coil(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, bool on, uint8_t *exc)
{
    return regmap_rtu_parse_write_single_coil_response(frame, len, slave, address, on, exc);
}

regmap_status m0_parse_write_multiple_coils(const uint8_t *frame, size_t len, uint8_t slave, uint16_t address, uint16_t count, uint8_t *exc)
{
    return regmap_rtu_parse_write_multiple_coils_response(frame, len, slave, address, count, exc);
}

float m0_f32(const uint16_t *words, regmap_word_order word_order, regmap_byte_order byte_order)
{
    return regmap_f32_from_wire(words, word_order, byte_order);
}

size_t m0_text(const uint16_t *words, size_t count, regmap_byte_order byte_order, regmap_padding padding, char *text, size_t size)
{
    return regmap_string_from_wire(words, count, byte_order, padding, text, size);
}
#endif
