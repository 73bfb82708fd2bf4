/*
 * Edge cases of the shared generated/c/regmap_rtu.h that the manuals' frames do not reach:
 * capacity and argument checks, every parse error, response lengths, and 16/32-bit word
 * conversions in both word orders. tests/test_c_backend.py compiles and runs it with every
 * host compiler (and with clang's sanitizers); the exit status is 0 when every check passes.
 */
#include <stdio.h>
#include <string.h>

#include "regmap_rtu.h"

static int checks;
static int failures;

#define CHECK(cond)                                                          \
    do {                                                                     \
        ++checks;                                                            \
        if (!(cond)) {                                                       \
            ++failures;                                                      \
            printf("FAIL %s:%d: %s\n", __FILE__, __LINE__, #cond);           \
        }                                                                    \
    } while (0)

/* A frame from its bytes without CRC: the CRC is appended with regmap_rtu_finish. */
static size_t frame_of(uint8_t *buf, size_t cap, const uint8_t *body, size_t len)
{
    memcpy(buf, body, len);
    return regmap_rtu_finish(buf, cap, len);
}

static void test_crc(void)
{
    static const uint8_t read_peak_current[] = { 0x01, 0x03, 0x01, 0x91, 0x00, 0x01, 0xD4, 0x1B };
    static const uint8_t check[] = { '1', '2', '3', '4', '5', '6', '7', '8', '9' };
    uint8_t bad[sizeof read_peak_current];
    CHECK(regmap_crc16(read_peak_current, 6u) == 0x1BD4u);
    CHECK(regmap_crc16(check, sizeof check) == 0x4B37u); /* CRC-16/MODBUS check value */
    CHECK(regmap_crc16(check, 0u) == 0xFFFFu);
    CHECK(regmap_rtu_crc_ok(read_peak_current, sizeof read_peak_current));
    memcpy(bad, read_peak_current, sizeof bad);
    bad[7] ^= 0x01u;
    CHECK(!regmap_rtu_crc_ok(bad, sizeof bad));
    CHECK(!regmap_rtu_crc_ok(read_peak_current, 3u));
    CHECK(!regmap_rtu_crc_ok(NULL, 8u));
}

static void test_builders(void)
{
    static const uint8_t read_peak_current[] = { 0x01, 0x03, 0x01, 0x91, 0x00, 0x01, 0xD4, 0x1B };
    static const uint8_t set_current[] = { 0x01, 0x06, 0x01, 0x91, 0x00, 0x0F, 0x99, 0xDF };
    static const uint8_t write_di[] = { 0x01, 0x10, 0x01, 0x46, 0x00, 0x04, 0x08, 0x00, 0x00, 0x00, 0x28, 0x00, 0x00, 0x00, 0x29, 0x1C, 0x14 };
    static const uint16_t di_words[] = { 0x0000, 0x0028, 0x0000, 0x0029 };
    uint16_t many[REGMAP_RTU_MAX_WRITE_REGISTERS + 1u];
    uint8_t buf[REGMAP_RTU_MAX_FRAME];
    memset(many, 0, sizeof many);

    CHECK(regmap_rtu_build_read(buf, sizeof buf, 1u, 0x0191u, 1u) == 8u && memcmp(buf, read_peak_current, 8u) == 0);
    CHECK(regmap_rtu_build_read(buf, 8u, 1u, 0x0191u, 1u) == 8u);
    CHECK(regmap_rtu_build_read(buf, 7u, 1u, 0x0191u, 1u) == 0u);
    CHECK(regmap_rtu_build_read(NULL, 8u, 1u, 0x0191u, 1u) == 0u);
    CHECK(regmap_rtu_build_read(buf, sizeof buf, 1u, 0x0191u, 0u) == 0u);
    CHECK(regmap_rtu_build_read(buf, sizeof buf, 1u, 0x0000u, 125u) == 8u);
    CHECK(regmap_rtu_build_read(buf, sizeof buf, 1u, 0x0000u, 126u) == 0u);
    CHECK(regmap_rtu_build_read(buf, sizeof buf, 1u, 0xFFFFu, 1u) == 8u);
    CHECK(regmap_rtu_build_read(buf, sizeof buf, 1u, 0xFFFFu, 2u) == 0u); /* would pass the end of the address space */

    CHECK(regmap_rtu_build_write_single(buf, sizeof buf, 1u, 0x0191u, 15u) == 8u && memcmp(buf, set_current, 8u) == 0);
    CHECK(regmap_rtu_build_write_single(buf, 7u, 1u, 0x0191u, 15u) == 0u);

    CHECK(regmap_rtu_build_write_multiple(buf, sizeof buf, 1u, 0x0146u, di_words, 4u) == sizeof write_di);
    CHECK(memcmp(buf, write_di, sizeof write_di) == 0);
    CHECK(regmap_rtu_build_write_multiple(buf, sizeof write_di, 1u, 0x0146u, di_words, 4u) == sizeof write_di);
    CHECK(regmap_rtu_build_write_multiple(buf, sizeof write_di - 1u, 1u, 0x0146u, di_words, 4u) == 0u);
    CHECK(regmap_rtu_build_write_multiple(buf, sizeof buf, 1u, 0x0146u, NULL, 4u) == 0u);
    CHECK(regmap_rtu_build_write_multiple(buf, sizeof buf, 1u, 0x0146u, di_words, 0u) == 0u);
    CHECK(regmap_rtu_build_write_multiple(buf, sizeof buf, 1u, 0x0000u, many, 123u) == REGMAP_RTU_WRITE_MULTIPLE_LEN(123u));
    CHECK(regmap_rtu_build_write_multiple(buf, sizeof buf, 1u, 0x0000u, many, 124u) == 0u);
    CHECK(regmap_rtu_build_write_multiple(buf, sizeof buf, 1u, 0xFFFFu, many, 2u) == 0u);

    CHECK(regmap_rtu_build_request(buf, sizeof buf, 1u, 0x02u, 0x0001u, 0x0001u) == 8u);
    CHECK(buf[6] == 0xE8u && buf[7] == 0x0Au);
    CHECK(regmap_rtu_finish(buf, sizeof buf, REGMAP_RTU_MAX_FRAME - 2u) == REGMAP_RTU_MAX_FRAME);
    CHECK(regmap_rtu_finish(buf, sizeof buf, REGMAP_RTU_MAX_FRAME - 1u) == 0u);
    CHECK(regmap_rtu_finish(buf, 5u, 4u) == 0u);
}

static void test_parsers(void)
{
    static const uint8_t read_rsp[] = { 0x01, 0x03, 0x04, 0x27, 0x10, 0x00, 0x00 };
    static const uint8_t exception_rsp[] = { 0x01, 0x83, 0x08 };
    static const uint8_t echo[] = { 0x01, 0x06, 0x01, 0x91, 0x00, 0x0F };
    static const uint8_t written[] = { 0x01, 0x10, 0x01, 0x46, 0x00, 0x04 };
    static const uint8_t odd[] = { 0x01, 0x03, 0x03, 0x27, 0x10, 0x00 };
    uint8_t frame[REGMAP_RTU_MAX_FRAME];
    uint16_t words[4];
    uint8_t exception = 0u;
    size_t len;

    len = frame_of(frame, sizeof frame, read_rsp, sizeof read_rsp);
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 2u, words, 4u, &exception) == REGMAP_OK);
    CHECK(words[0] == 0x2710u && words[1] == 0x0000u);
    CHECK(regmap_u32_from_words(words, REGMAP_LOW_FIRST) == 10000u);
    CHECK(regmap_rtu_parse_read_response(frame, len, 2u, 2u, words, 4u, &exception) == REGMAP_ERR_SLAVE);
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 1u, words, 4u, &exception) == REGMAP_ERR_BYTE_COUNT);
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 2u, words, 1u, &exception) == REGMAP_ERR_ARGUMENT);
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 0u, words, 4u, &exception) == REGMAP_ERR_ARGUMENT);
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 2u, NULL, 4u, &exception) == REGMAP_ERR_ARGUMENT);
    CHECK(regmap_rtu_parse_read_response(frame, len - 1u, 1u, 2u, words, 4u, &exception) == REGMAP_ERR_CRC);
    CHECK(regmap_rtu_parse_read_response(frame, 4u, 1u, 2u, words, 4u, &exception) == REGMAP_ERR_LENGTH);
    CHECK(regmap_rtu_parse_read_response(NULL, len, 1u, 2u, words, 4u, &exception) == REGMAP_ERR_LENGTH);
    frame[3] ^= 0x01u;
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 2u, words, 4u, &exception) == REGMAP_ERR_CRC);
    len = frame_of(frame, sizeof frame, odd, sizeof odd);
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 2u, words, 4u, &exception) == REGMAP_ERR_BYTE_COUNT);
    len = frame_of(frame, sizeof frame, read_rsp, sizeof read_rsp - 1u); /* byte count says 4, 3 follow */
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 2u, words, 4u, &exception) == REGMAP_ERR_LENGTH);

    len = frame_of(frame, sizeof frame, exception_rsp, sizeof exception_rsp);
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 1u, words, 4u, &exception) == REGMAP_ERR_EXCEPTION);
    CHECK(exception == 0x08u);
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 1u, words, 4u, NULL) == REGMAP_ERR_EXCEPTION);
    CHECK(regmap_rtu_parse_write_single_response(frame, len, 1u, 0u, 0u, &exception) == REGMAP_ERR_FUNCTION);
    CHECK(regmap_rtu_check_response(frame, len, 1u, 0x03u, &exception) == REGMAP_ERR_EXCEPTION);

    len = frame_of(frame, sizeof frame, echo, sizeof echo);
    CHECK(regmap_rtu_parse_write_single_response(frame, len, 1u, 0x0191u, 15u, &exception) == REGMAP_OK);
    CHECK(regmap_rtu_parse_write_single_response(frame, len, 1u, 0x0191u, 16u, &exception) == REGMAP_ERR_ECHO);
    CHECK(regmap_rtu_parse_write_single_response(frame, len, 1u, 0x0190u, 15u, &exception) == REGMAP_ERR_ECHO);
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 1u, words, 4u, &exception) == REGMAP_ERR_FUNCTION);

    len = frame_of(frame, sizeof frame, written, sizeof written);
    CHECK(regmap_rtu_parse_write_multiple_response(frame, len, 1u, 0x0146u, 4u, &exception) == REGMAP_OK);
    CHECK(regmap_rtu_parse_write_multiple_response(frame, len, 1u, 0x0146u, 3u, &exception) == REGMAP_ERR_ECHO);
    CHECK(regmap_rtu_parse_write_multiple_response(frame, len, 1u, 0x0147u, 4u, &exception) == REGMAP_ERR_ECHO);

    CHECK(regmap_rtu_response_len(read_rsp, 2u) == 0u);
    CHECK(regmap_rtu_response_len(read_rsp, 3u) == 9u);
    CHECK(regmap_rtu_response_len(exception_rsp, 3u) == REGMAP_RTU_EXCEPTION_LEN);
    CHECK(regmap_rtu_response_len(echo, 3u) == 8u);
    CHECK(regmap_rtu_response_len(written, 3u) == 8u);
    CHECK(regmap_rtu_response_len(NULL, 3u) == 0u);
}

static void test_words(void)
{
    uint16_t words[2];
    regmap_u32_to_words(0x00030D40ul, REGMAP_HIGH_FIRST, words);
    CHECK(words[0] == 0x0003u && words[1] == 0x0D40u);
    CHECK(regmap_u32_from_words(words, REGMAP_HIGH_FIRST) == 200000ul);
    regmap_u32_to_words(0x00030D40ul, REGMAP_LOW_FIRST, words);
    CHECK(words[0] == 0x0D40u && words[1] == 0x0003u);
    CHECK(regmap_u32_from_words(words, REGMAP_LOW_FIRST) == 200000ul);
    regmap_s32_to_words(-200000, REGMAP_HIGH_FIRST, words);
    CHECK(words[0] == 0xFFFCu && words[1] == 0xF2C0u); /* iDM-RS 7.4 */
    CHECK(regmap_s32_from_words(words, REGMAP_HIGH_FIRST) == -200000);
    regmap_s32_to_words(-200000, REGMAP_LOW_FIRST, words);
    CHECK(words[0] == 0xF2C0u && words[1] == 0xFFFCu);
    CHECK(regmap_s32_from_words(words, REGMAP_LOW_FIRST) == -200000);
    regmap_s32_to_words(INT32_MIN, REGMAP_HIGH_FIRST, words);
    CHECK(words[0] == 0x8000u && words[1] == 0x0000u && regmap_s32_from_words(words, REGMAP_HIGH_FIRST) == INT32_MIN);
    regmap_s32_to_words(INT32_MAX, REGMAP_LOW_FIRST, words);
    CHECK(regmap_s32_from_words(words, REGMAP_LOW_FIRST) == INT32_MAX);
    regmap_s32_to_words(-1, REGMAP_LOW_FIRST, words);
    CHECK(words[0] == 0xFFFFu && words[1] == 0xFFFFu && regmap_u32_from_words(words, REGMAP_LOW_FIRST) == 0xFFFFFFFFul);
    CHECK(regmap_s16_from_word(0xFFFFu) == -1);
    CHECK(regmap_s16_from_word(0x8000u) == INT16_MIN);
    CHECK(regmap_s16_from_word(0x7FFFu) == INT16_MAX);
    CHECK(regmap_s16_to_word(-6000) == 0xE890u);
    CHECK(regmap_s16_to_word(INT16_MIN) == 0x8000u);
    CHECK(regmap_pair_high_word(0x0028u, false) == 0x0000u);
    CHECK(regmap_pair_high_word(0xE890u, false) == 0x0000u);
    CHECK(regmap_pair_high_word(0xE890u, true) == 0xFFFFu);
    CHECK(regmap_pair_high_word(0x1770u, true) == 0x0000u);
    CHECK(regmap_get_be16((const uint8_t *)"\x12\x34") == 0x1234u);
}

static void test_status_text(void)
{
    CHECK(strcmp(regmap_status_text(REGMAP_OK), "ok") == 0);
    CHECK(strcmp(regmap_status_text(REGMAP_ERR_ECHO), "echo mismatch") == 0);
    CHECK(strcmp(regmap_status_text(REGMAP_ERR_EXCEPTION), "exception response") == 0);
}

int main(void)
{
    test_crc();
    test_builders();
    test_parsers();
    test_words();
    test_status_text();
    printf("regmap_rtu.h self-test: %d checks, %d failures\n", checks, failures);
    return failures == 0 ? 0 : 1;
}
