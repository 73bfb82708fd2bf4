/* libFuzzer harness for the generated RTU response parsers (issue 12).
 * The first input byte picks the parser and its expectations; the rest is the frame.
 * AddressSanitizer and UBSan catch any read or write outside the buffers. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "regmap_rtu.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1u) {
        return 0;
    }
    uint8_t selector = data[0];
    const uint8_t *frame = data + 1;
    size_t len = size - 1u;
    /* An exact-size heap copy, so AddressSanitizer sees the true end of the frame. */
    uint8_t *copy = (uint8_t *)malloc(len > 0u ? len : 1u);
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
    switch (selector % 4u) {
    case 0:
        (void)regmap_rtu_parse_read_response(copy, len, slave, count, words, (size_t)(selector % 8u), &exception);
        break;
    case 1:
        (void)regmap_rtu_parse_read_response(copy, len, slave, count, words, REGMAP_RTU_MAX_READ_REGISTERS, &exception);
        break;
    case 2:
        (void)regmap_rtu_parse_write_single_response(copy, len, slave, (uint16_t)(selector * 257u), (uint16_t)selector, &exception);
        break;
    default:
        (void)regmap_rtu_parse_write_multiple_response(copy, len, slave, (uint16_t)(selector * 257u), count, &exception);
        break;
    }
    (void)regmap_rtu_check_response(copy, len, slave, (uint8_t)(selector & 0x7Fu), &exception);
    free(copy);
    return 0;
}
