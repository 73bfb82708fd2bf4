/* libFuzzer harness for the generated RTU response parsers (issue 12) and the parsers and copies of
 * issue 19: coil, discrete-input and input-register responses, coil write echoes, the string copy
 * both ways, bit unpacking and firmware version texts.
 * The first input byte picks the parser and its expectations; the rest is the frame.
 * AddressSanitizer and UBSan catch any read or write outside the buffers: every buffer handed to a
 * helper is an exact-size heap block, so one byte too far is caught. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "regmap_rtu.h"

#define PARSERS 11u

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void *exact(size_t len)
{
    return malloc(len > 0u ? len : 1u);
}

/* A read of bits: the count from the frame's byte count (so well-formed frames get through), a bit
 * buffer of exactly `count` or one less (so a parser that ignores its capacity is caught). */
static void fuzz_bits(const uint8_t *frame, size_t len, uint8_t slave, uint8_t selector, bool coils)
{
    uint8_t exception = 0u;
    uint16_t count = len > 2u ? (uint16_t)((unsigned)frame[2] * 8u - (selector % 8u)) : (uint16_t)(1u + selector);
    size_t cap = (selector & 0x10u) != 0u && count > 1u ? (size_t)count - 1u : (size_t)count;
    bool *bits = (bool *)exact(cap * sizeof(bool));
    if (bits == NULL) {
        return;
    }
    if (coils) {
        (void)regmap_rtu_parse_read_coils_response(frame, len, slave, count, bits, cap, &exception);
    } else {
        (void)regmap_rtu_parse_read_discrete_inputs_response(frame, len, slave, count, bits, cap, &exception);
    }
    free(bits);
}

/* The string copy both ways on the frame's bytes: as register words to text of a size the selector
 * picks, and as text (no NUL guaranteed, so the count keeps the bytes looked at within the frame). */
static void fuzz_strings(const uint8_t *frame, size_t len, uint8_t selector)
{
    size_t count = len / 2u;
    size_t size = selector % 24u;
    regmap_byte_order order = (selector & 0x40u) != 0u ? REGMAP_LOW_FIRST : REGMAP_HIGH_FIRST;
    regmap_padding padding = (selector & 0x80u) != 0u ? REGMAP_PADDING_SPACE : REGMAP_PADDING_NUL;
    uint16_t *words = (uint16_t *)exact(count * sizeof(uint16_t));
    char *text = (char *)exact(size);
    size_t i;
    uint32_t version = 0u;
    if (words != NULL && text != NULL) {
        for (i = 0u; i < count; ++i) {
            words[i] = regmap_get_be16(&frame[2u * i]);
        }
        (void)regmap_string_from_wire(words, count, order, padding, text, size);
        (void)regmap_string_from_wire(words, count, order, padding, NULL, size);
        if (len > 0u) {
            /* at most 2 * count + 1 bytes of the text are looked at: (len - 1) / 2 words keep that within len */
            (void)regmap_string_to_wire((const char *)frame, order, padding, words, (len - 1u) / 2u);
        }
        (void)regmap_version_from_text((const char *)frame, len, &version);
    }
    free(words);
    free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1u) {
        return 0;
    }
    uint8_t selector = data[0];
    const uint8_t *frame = data + 1;
    size_t len = size - 1u;
    /* An exact-size heap copy, so AddressSanitizer sees the true end of the frame. */
    uint8_t *copy = (uint8_t *)exact(len);
    if (copy == NULL) {
        return 0;
    }
    memcpy(copy, frame, len);
    uint8_t exception = 0u;
    uint16_t words[REGMAP_RTU_MAX_READ_REGISTERS];
    uint16_t count = (uint16_t)(1u + (selector % REGMAP_RTU_MAX_READ_REGISTERS));
    uint8_t slave = len > 0u ? copy[0] : 1u;
    (void)regmap_rtu_response_len(copy, len);
    (void)regmap_rtu_crc_ok(copy, len);
    switch (selector % PARSERS) {
    case 0:
        (void)regmap_rtu_parse_read_response(copy, len, slave, count, words, (size_t)(selector % 8u), &exception);
        break;
    case 1:
        (void)regmap_rtu_parse_read_response(copy, len, slave, count, words, REGMAP_RTU_MAX_READ_REGISTERS, &exception);
        break;
    case 2:
        (void)regmap_rtu_parse_write_single_response(copy, len, slave, (uint16_t)(selector * 257u), (uint16_t)selector, &exception);
        break;
    case 3:
        (void)regmap_rtu_parse_write_multiple_response(copy, len, slave, (uint16_t)(selector * 257u), count, &exception);
        break;
    case 4:
        if (len > 2u) {
            count = (uint16_t)(copy[2] / 2u > 0u ? copy[2] / 2u : 1u);
        }
        (void)regmap_rtu_parse_read_input_response(copy, len, slave, count, words, REGMAP_RTU_MAX_READ_REGISTERS, &exception);
        break;
    case 5:
        fuzz_bits(copy, len, slave, selector, true);
        break;
    case 6:
        fuzz_bits(copy, len, slave, selector, false);
        break;
    case 7:
        (void)regmap_rtu_parse_write_single_coil_response(copy, len, slave, len > 3u ? regmap_get_be16(&copy[2]) : 0u, (selector & 0x10u) != 0u,
                                                          &exception);
        break;
    case 8:
        (void)regmap_rtu_parse_write_multiple_coils_response(copy, len, slave, len > 3u ? regmap_get_be16(&copy[2]) : 0u,
                                                             (uint16_t)(selector * 8u), &exception);
        break;
    case 9:
        fuzz_strings(copy, len, selector);
        break;
    default: {
        bool *bits = (bool *)exact(len * 8u * sizeof(bool));
        if (bits != NULL) {
            (void)regmap_bits_unpack(copy, len * 8u, bits);
            (void)regmap_bits_pack(bits, len * 8u, copy, len);
        }
        free(bits);
        break;
    }
    }
    (void)regmap_rtu_check_response(copy, len, slave, (uint8_t)(selector & 0x7Fu), &exception);
    free(copy);
    return 0;
}
