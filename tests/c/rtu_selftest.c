/*
 * Edge cases of the shared generated/c/regmap_rtu.h that the manuals' frames do not reach:
 * capacity and argument checks, every parse error, response lengths, 16/32/64-bit and float
 * conversions in every word and byte order, strings, coil bits and firmware versions. The
 * coil, input-register and discrete-input frames are the Modbus Application Protocol v1.1b3's
 * worked examples (section 6.1-6.11, slave 1, RTU CRC). tests/backends/c/test_c_backend.py compiles and
 * runs it with every host compiler (and with clang's sanitizers); the exit status is 0 when
 * every check passes.
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

static void test_bit_builders(void)
{
    static const uint8_t read_coils[] = { 0x01, 0x01, 0x00, 0x13, 0x00, 0x13, 0x8C, 0x02 };       /* 6.1 */
    static const uint8_t read_inputs[] = { 0x01, 0x02, 0x00, 0xC4, 0x00, 0x16, 0xB8, 0x39 };      /* 6.2 */
    static const uint8_t read_input_regs[] = { 0x01, 0x04, 0x00, 0x08, 0x00, 0x01, 0xB0, 0x08 };  /* 6.4 */
    static const uint8_t coil_on[] = { 0x01, 0x05, 0x00, 0xAC, 0xFF, 0x00, 0x4C, 0x1B };          /* 6.5 */
    static const uint8_t coil_off[] = { 0x01, 0x05, 0x00, 0xAC, 0x00, 0x00, 0x0D, 0xEB };
    static const uint8_t write_coils[] = { 0x01, 0x0F, 0x00, 0x13, 0x00, 0x0A, 0x02, 0xCD, 0x01, 0x72, 0xCB }; /* 6.11 */
    static const bool ten[] = { true, false, true, true, false, false, true, true, true, false };
    static bool many[REGMAP_RTU_MAX_READ_BITS + 1u];
    uint8_t buf[REGMAP_RTU_MAX_FRAME];

    CHECK(regmap_rtu_build_read_coils(buf, sizeof buf, 1u, 0x0013u, 19u) == 8u && memcmp(buf, read_coils, 8u) == 0);
    CHECK(regmap_rtu_build_read_discrete_inputs(buf, sizeof buf, 1u, 0x00C4u, 22u) == 8u && memcmp(buf, read_inputs, 8u) == 0);
    CHECK(regmap_rtu_build_read_input_registers(buf, sizeof buf, 1u, 0x0008u, 1u) == 8u && memcmp(buf, read_input_regs, 8u) == 0);
    CHECK(regmap_rtu_build_read_coils(buf, sizeof buf, 1u, 0x0000u, 2000u) == 8u);
    CHECK(regmap_rtu_build_read_coils(buf, sizeof buf, 1u, 0x0000u, 2001u) == 0u);
    CHECK(regmap_rtu_build_read_coils(buf, sizeof buf, 1u, 0x0000u, 0u) == 0u);
    CHECK(regmap_rtu_build_read_coils(buf, sizeof buf, 1u, 0xFFFFu, 1u) == 8u);
    CHECK(regmap_rtu_build_read_coils(buf, sizeof buf, 1u, 0xFFFFu, 2u) == 0u);
    CHECK(regmap_rtu_build_read_discrete_inputs(buf, sizeof buf, 1u, 0x0000u, 2001u) == 0u);
    CHECK(regmap_rtu_build_read_discrete_inputs(buf, 7u, 1u, 0x0000u, 1u) == 0u);
    CHECK(regmap_rtu_build_read_input_registers(buf, sizeof buf, 1u, 0x0000u, 125u) == 8u);
    CHECK(regmap_rtu_build_read_input_registers(buf, sizeof buf, 1u, 0x0000u, 126u) == 0u);
    CHECK(regmap_rtu_build_read_input_registers(buf, sizeof buf, 1u, 0xFFFEu, 3u) == 0u);
    CHECK(buf[1] == 0x04u); /* the last frame built stays: the refused ones wrote nothing useful but no more */

    CHECK(regmap_rtu_build_write_single_coil(buf, sizeof buf, 1u, 0x00ACu, true) == 8u && memcmp(buf, coil_on, 8u) == 0);
    CHECK(regmap_rtu_build_write_single_coil(buf, sizeof buf, 1u, 0x00ACu, false) == 8u && memcmp(buf, coil_off, 8u) == 0);
    CHECK(regmap_rtu_build_write_single_coil(buf, 7u, 1u, 0x00ACu, true) == 0u);

    CHECK(regmap_rtu_build_write_multiple_coils(buf, sizeof buf, 1u, 0x0013u, ten, 10u) == sizeof write_coils);
    CHECK(memcmp(buf, write_coils, sizeof write_coils) == 0);
    CHECK(regmap_rtu_build_write_multiple_coils(buf, sizeof write_coils, 1u, 0x0013u, ten, 10u) == sizeof write_coils);
    CHECK(regmap_rtu_build_write_multiple_coils(buf, sizeof write_coils - 1u, 1u, 0x0013u, ten, 10u) == 0u);
    CHECK(regmap_rtu_build_write_multiple_coils(buf, sizeof buf, 1u, 0x0013u, NULL, 10u) == 0u);
    CHECK(regmap_rtu_build_write_multiple_coils(NULL, sizeof buf, 1u, 0x0013u, ten, 10u) == 0u);
    CHECK(regmap_rtu_build_write_multiple_coils(buf, sizeof buf, 1u, 0x0013u, ten, 0u) == 0u);
    memset(many, 0, sizeof many);
    many[1967] = true;
    CHECK(regmap_rtu_build_write_multiple_coils(buf, sizeof buf, 1u, 0x0000u, many, 1968u) == REGMAP_RTU_WRITE_BITS_LEN(1968u));
    CHECK(REGMAP_RTU_WRITE_BITS_LEN(1968u) == 255u && buf[6] == 246u && buf[7u + 245u] == 0x80u);
    CHECK(regmap_rtu_build_write_multiple_coils(buf, sizeof buf, 1u, 0x0000u, many, 1969u) == 0u);
    CHECK(regmap_rtu_build_write_multiple_coils(buf, sizeof buf, 1u, 0xFFFFu, many, 2u) == 0u);
    CHECK(regmap_rtu_build_write_multiple_coils(buf, sizeof buf, 1u, 0x0000u, many, 9u) == REGMAP_RTU_WRITE_BITS_LEN(9u));
    CHECK(buf[6] == 2u && buf[7] == 0x00u && buf[8] == 0x00u); /* the padding bits of the last byte are 0 */
}

static void test_bit_parsers(void)
{
    static const uint8_t coils_rsp[] = { 0x01, 0x01, 0x03, 0xCD, 0x6B, 0x05 };   /* 6.1: coils 20..38 */
    static const uint8_t inputs_rsp[] = { 0x01, 0x02, 0x03, 0xAC, 0xDB, 0x35 };  /* 6.2: inputs 197..218 */
    static const uint8_t input_reg_rsp[] = { 0x01, 0x04, 0x02, 0x00, 0x0A };     /* 6.4: register 9 is 10 */
    static const uint8_t coil_echo[] = { 0x01, 0x05, 0x00, 0xAC, 0xFF, 0x00 };   /* 6.5 */
    static const uint8_t coils_written[] = { 0x01, 0x0F, 0x00, 0x13, 0x00, 0x0A }; /* 6.11 */
    static const uint8_t coil_exception[] = { 0x01, 0x81, 0x02 };
    static const bool coils[19] = { true, false, true, true, false, false, true, true,   /* CD */
                                    true, true, false, true, false, true, true, false,  /* 6B */
                                    true, false, true };                                 /* 05 */
    uint8_t frame[REGMAP_RTU_MAX_FRAME];
    bool bits[24];
    uint16_t words[2];
    uint8_t exception = 0u;
    size_t len;
    unsigned i;
    bool same = true;

    len = frame_of(frame, sizeof frame, coils_rsp, sizeof coils_rsp);
    memset(bits, 0, sizeof bits);
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 1u, 19u, bits, 24u, &exception) == REGMAP_OK);
    for (i = 0u; i < 19u; ++i) {
        same = same && bits[i] == coils[i];
    }
    CHECK(same);
    CHECK(!bits[19]); /* nothing past the count is written */
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 1u, 17u, bits, 24u, &exception) == REGMAP_OK); /* 17..24 bits: 3 bytes */
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 1u, 24u, bits, 24u, &exception) == REGMAP_OK);
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 1u, 16u, bits, 24u, &exception) == REGMAP_ERR_BYTE_COUNT);
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 1u, 25u, bits, 24u, &exception) == REGMAP_ERR_ARGUMENT); /* bits_cap */
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 1u, 19u, bits, 18u, &exception) == REGMAP_ERR_ARGUMENT);
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 1u, 0u, bits, 24u, &exception) == REGMAP_ERR_ARGUMENT);
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 1u, 19u, NULL, 24u, &exception) == REGMAP_ERR_ARGUMENT);
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 2u, 19u, bits, 24u, &exception) == REGMAP_ERR_SLAVE);
    CHECK(regmap_rtu_parse_read_discrete_inputs_response(frame, len, 1u, 19u, bits, 24u, &exception) == REGMAP_ERR_FUNCTION);
    CHECK(regmap_rtu_parse_read_coils_response(frame, len - 1u, 1u, 19u, bits, 24u, &exception) == REGMAP_ERR_CRC);
    len = frame_of(frame, sizeof frame, coils_rsp, sizeof coils_rsp - 1u); /* byte count 3, two bytes follow */
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 1u, 19u, bits, 24u, &exception) == REGMAP_ERR_LENGTH);

    len = frame_of(frame, sizeof frame, inputs_rsp, sizeof inputs_rsp);
    CHECK(regmap_rtu_parse_read_discrete_inputs_response(frame, len, 1u, 22u, bits, 24u, &exception) == REGMAP_OK);
    CHECK(!bits[0] && !bits[1] && bits[2] && bits[7] && bits[8] && bits[16] && !bits[17] && bits[21]);
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 1u, 22u, bits, 24u, &exception) == REGMAP_ERR_FUNCTION);

    len = frame_of(frame, sizeof frame, coil_exception, sizeof coil_exception);
    exception = 0u;
    CHECK(regmap_rtu_parse_read_coils_response(frame, len, 1u, 19u, bits, 24u, &exception) == REGMAP_ERR_EXCEPTION && exception == 0x02u);
    CHECK(regmap_rtu_parse_read_discrete_inputs_response(frame, len, 1u, 19u, bits, 24u, &exception) == REGMAP_ERR_FUNCTION);

    len = frame_of(frame, sizeof frame, input_reg_rsp, sizeof input_reg_rsp);
    CHECK(regmap_rtu_parse_read_input_response(frame, len, 1u, 1u, words, 2u, &exception) == REGMAP_OK && words[0] == 10u);
    CHECK(regmap_rtu_parse_read_response(frame, len, 1u, 1u, words, 2u, &exception) == REGMAP_ERR_FUNCTION);
    CHECK(regmap_rtu_parse_read_input_response(frame, len, 1u, 2u, words, 2u, &exception) == REGMAP_ERR_BYTE_COUNT);
    CHECK(regmap_rtu_parse_read_input_response(frame, len, 1u, 1u, words, 0u, &exception) == REGMAP_ERR_ARGUMENT);

    len = frame_of(frame, sizeof frame, coil_echo, sizeof coil_echo);
    CHECK(regmap_rtu_parse_write_single_coil_response(frame, len, 1u, 0x00ACu, true, &exception) == REGMAP_OK);
    CHECK(regmap_rtu_parse_write_single_coil_response(frame, len, 1u, 0x00ACu, false, &exception) == REGMAP_ERR_ECHO);
    CHECK(regmap_rtu_parse_write_single_coil_response(frame, len, 1u, 0x00ADu, true, &exception) == REGMAP_ERR_ECHO);
    CHECK(regmap_rtu_parse_write_single_response(frame, len, 1u, 0x00ACu, 0xFF00u, &exception) == REGMAP_ERR_FUNCTION);

    len = frame_of(frame, sizeof frame, coils_written, sizeof coils_written);
    CHECK(regmap_rtu_parse_write_multiple_coils_response(frame, len, 1u, 0x0013u, 10u, &exception) == REGMAP_OK);
    CHECK(regmap_rtu_parse_write_multiple_coils_response(frame, len, 1u, 0x0013u, 11u, &exception) == REGMAP_ERR_ECHO);
    CHECK(regmap_rtu_parse_write_multiple_response(frame, len, 1u, 0x0013u, 10u, &exception) == REGMAP_ERR_FUNCTION);
    CHECK(regmap_rtu_parse_write_multiple_coils_response(frame, len - 1u, 1u, 0x0013u, 10u, &exception) == REGMAP_ERR_CRC);

    CHECK(regmap_rtu_response_len(coils_rsp, 3u) == 8u);
    CHECK(regmap_rtu_response_len(inputs_rsp, 3u) == 8u);
    CHECK(regmap_rtu_response_len(input_reg_rsp, 3u) == 7u);
    CHECK(regmap_rtu_response_len(coil_echo, 3u) == 8u);
    CHECK(regmap_rtu_response_len(coils_written, 3u) == 8u);
    CHECK(regmap_rtu_response_len(coil_exception, 3u) == REGMAP_RTU_EXCEPTION_LEN);
    CHECK(REGMAP_RTU_READ_BITS_RESPONSE_LEN(19u) == 8u && REGMAP_RTU_READ_BITS_RESPONSE_LEN(2000u) == 255u);
}

static void test_bits(void)
{
    static const bool pattern[10] = { true, false, true, true, false, false, true, true, true, false };
    uint8_t bytes[3] = { 0xAAu, 0xAAu, 0xAAu };
    bool bits[10];
    CHECK(regmap_bits_pack(pattern, 10u, bytes, 3u) == 2u && bytes[0] == 0xCDu && bytes[1] == 0x01u && bytes[2] == 0xAAu);
    CHECK(regmap_bits_pack(pattern, 10u, bytes, 1u) == 0u);
    CHECK(regmap_bits_pack(pattern, 0u, bytes, 3u) == 0u);
    CHECK(regmap_bits_pack(NULL, 1u, bytes, 3u) == 0u);
    CHECK(regmap_bits_pack(pattern, 8u, bytes, 1u) == 1u && bytes[0] == 0xCDu);
    CHECK(regmap_bits_unpack(bytes, 0u, bits));
    CHECK(!regmap_bits_unpack(NULL, 1u, bits));
    bytes[0] = 0x80u;
    bytes[1] = 0x01u;
    CHECK(regmap_bits_unpack(bytes, 10u, bits) && bits[7] && bits[8] && !bits[0] && !bits[9]);
}

static void test_wire_values(void)
{
    /* 0x12345678 as ABCD, CDAB, BADC, DCBA (the wire bytes, two to a word) */
    static const uint16_t abcd[2] = { 0x1234u, 0x5678u };
    static const uint16_t cdab[2] = { 0x5678u, 0x1234u };
    static const uint16_t badc[2] = { 0x3412u, 0x7856u };
    static const uint16_t dcba[2] = { 0x7856u, 0x3412u };
    /* 1234.5678 as a double: 40 93 4A 45 6D 5C FA AD (struct.pack(">d")) */
    static const uint16_t f64_abcd[4] = { 0x4093u, 0x4A45u, 0x6D5Cu, 0xFAADu };
    static const uint16_t f64_dcba[4] = { 0xADFAu, 0x5C6Du, 0x454Au, 0x9340u };
    uint16_t w[4];
    CHECK(regmap_u32_from_wire(abcd, REGMAP_HIGH_FIRST, REGMAP_HIGH_FIRST) == 0x12345678ul);
    CHECK(regmap_u32_from_wire(cdab, REGMAP_LOW_FIRST, REGMAP_HIGH_FIRST) == 0x12345678ul);
    CHECK(regmap_u32_from_wire(badc, REGMAP_HIGH_FIRST, REGMAP_LOW_FIRST) == 0x12345678ul);
    CHECK(regmap_u32_from_wire(dcba, REGMAP_LOW_FIRST, REGMAP_LOW_FIRST) == 0x12345678ul);
    regmap_u32_to_wire(0x12345678ul, REGMAP_LOW_FIRST, REGMAP_LOW_FIRST, w);
    CHECK(w[0] == dcba[0] && w[1] == dcba[1]);
    regmap_u32_to_wire(0x12345678ul, REGMAP_HIGH_FIRST, REGMAP_LOW_FIRST, w);
    CHECK(w[0] == badc[0] && w[1] == badc[1]);
    CHECK(regmap_u32_from_wire(cdab, REGMAP_LOW_FIRST, REGMAP_HIGH_FIRST) == regmap_u32_from_words(cdab, REGMAP_LOW_FIRST));
    regmap_s32_to_wire(INT32_MIN, REGMAP_LOW_FIRST, REGMAP_LOW_FIRST, w);
    CHECK(w[0] == 0x0000u && w[1] == 0x0080u && regmap_s32_from_wire(w, REGMAP_LOW_FIRST, REGMAP_LOW_FIRST) == INT32_MIN);
    CHECK(regmap_u16_from_wire(0x0302u, REGMAP_LOW_FIRST) == 0x0203u && regmap_u16_from_wire(0x0302u, REGMAP_HIGH_FIRST) == 0x0302u);
    CHECK(regmap_s16_from_wire(0x00FFu, REGMAP_LOW_FIRST) == -256 && regmap_s16_to_wire(-256, REGMAP_LOW_FIRST) == 0x00FFu);
    CHECK(regmap_u16_to_wire(0x1234u, REGMAP_LOW_FIRST) == 0x3412u);

    regmap_u64_to_wire(0x0102030405060708ull, REGMAP_HIGH_FIRST, REGMAP_HIGH_FIRST, w);
    CHECK(w[0] == 0x0102u && w[1] == 0x0304u && w[2] == 0x0506u && w[3] == 0x0708u);
    CHECK(regmap_u64_from_wire(w, REGMAP_HIGH_FIRST, REGMAP_HIGH_FIRST) == 0x0102030405060708ull);
    regmap_u64_to_wire(0x0102030405060708ull, REGMAP_LOW_FIRST, REGMAP_HIGH_FIRST, w);
    CHECK(w[0] == 0x0708u && w[1] == 0x0506u && w[2] == 0x0304u && w[3] == 0x0102u);
    regmap_u64_to_wire(0x0102030405060708ull, REGMAP_LOW_FIRST, REGMAP_LOW_FIRST, w);
    CHECK(w[0] == 0x0807u && w[3] == 0x0201u && regmap_u64_from_wire(w, REGMAP_LOW_FIRST, REGMAP_LOW_FIRST) == 0x0102030405060708ull);
    regmap_s64_to_wire(-2, REGMAP_HIGH_FIRST, REGMAP_HIGH_FIRST, w);
    CHECK(w[0] == 0xFFFFu && w[3] == 0xFFFEu && regmap_s64_from_wire(w, REGMAP_HIGH_FIRST, REGMAP_HIGH_FIRST) == -2);
    regmap_s64_to_wire(INT64_MIN, REGMAP_HIGH_FIRST, REGMAP_LOW_FIRST, w);
    CHECK(w[0] == 0x0080u && w[1] == 0u && regmap_s64_from_wire(w, REGMAP_HIGH_FIRST, REGMAP_LOW_FIRST) == INT64_MIN);
    regmap_s64_to_wire(INT64_MAX, REGMAP_LOW_FIRST, REGMAP_HIGH_FIRST, w);
    CHECK(regmap_s64_from_wire(w, REGMAP_LOW_FIRST, REGMAP_HIGH_FIRST) == INT64_MAX);

#if REGMAP_HAS_F32
    CHECK(regmap_f32_to_bits(230.5f) == 0x43668000ul);
    CHECK(regmap_f32_to_bits(-0.0f) == 0x80000000ul);
    CHECK(regmap_f32_from_bits(0x7F800000ul) > 3.4e38f);
    w[0] = 0x0000u;
    w[1] = 0x4144u; /* 12.25 low word first (CDAB) */
    CHECK(regmap_f32_from_wire(w, REGMAP_LOW_FIRST, REGMAP_HIGH_FIRST) == 12.25f);
    regmap_f32_to_wire(12.25f, REGMAP_HIGH_FIRST, REGMAP_LOW_FIRST, w);
    CHECK(w[0] == 0x4441u && w[1] == 0x0000u);
#endif
#if REGMAP_HAS_F64
    CHECK(regmap_f64_from_wire(f64_abcd, REGMAP_HIGH_FIRST, REGMAP_HIGH_FIRST) == 1234.5678);
    CHECK(regmap_f64_from_wire(f64_dcba, REGMAP_LOW_FIRST, REGMAP_LOW_FIRST) == 1234.5678);
    regmap_f64_to_wire(1234.5678, REGMAP_LOW_FIRST, REGMAP_LOW_FIRST, w);
    CHECK(memcmp(w, f64_dcba, sizeof w) == 0);
    CHECK(regmap_f64_to_bits(-0.0) == 0x8000000000000000ull);
#else
    (void)f64_abcd;
    (void)f64_dcba;
#endif
}

static void test_strings(void)
{
    /* "PM-3000" NUL padded in 8 words; "AB12  " space padded in 3 words; "AXIS-01" byte-swapped */
    static const uint16_t model[8] = { 0x504Du, 0x2D33u, 0x3030u, 0x3000u, 0u, 0u, 0u, 0u };
    static const uint16_t spaced[3] = { 0x4142u, 0x2020u, 0x2020u };
    static const uint16_t swapped[4] = { 0x5841u, 0x5349u, 0x302Du, 0x0031u };
    static const uint16_t full[2] = { 0x4142u, 0x4344u };
    static const uint16_t inner_space[3] = { 0x4120u, 0x4220u, 0x2000u };
    static const uint16_t high_bytes[1] = { 0xC3A9u }; /* UTF-8 e-acute: copied as bytes */
    char text[17];
    uint16_t w[8];
    size_t i;

    CHECK(regmap_string_from_wire(model, 8u, REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, text, sizeof text) == 7u && strcmp(text, "PM-3000") == 0);
    CHECK(regmap_string_from_wire(model, 8u, REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, text, 4u) == 7u && strcmp(text, "PM-") == 0);
    CHECK(regmap_string_from_wire(model, 8u, REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, text, 1u) == 7u && text[0] == '\0');
    text[0] = 'x';
    CHECK(regmap_string_from_wire(model, 8u, REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, text, 0u) == 7u && text[0] == 'x');
    CHECK(regmap_string_from_wire(model, 8u, REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, NULL, 5u) == 7u);
    CHECK(regmap_string_from_wire(NULL, 8u, REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, text, sizeof text) == 0u && text[0] == '\0');
    CHECK(regmap_string_from_wire(spaced, 3u, REGMAP_HIGH_FIRST, REGMAP_PADDING_SPACE, text, sizeof text) == 2u && strcmp(text, "AB") == 0);
    CHECK(regmap_string_from_wire(spaced, 3u, REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, text, sizeof text) == 6u && strcmp(text, "AB    ") == 0);
    /* "A B  " then NUL: only the trailing spaces go, the inner one stays */
    CHECK(regmap_string_from_wire(inner_space, 3u, REGMAP_HIGH_FIRST, REGMAP_PADDING_SPACE, text, sizeof text) == 3u && strcmp(text, "A B") == 0);
    CHECK(regmap_string_from_wire(swapped, 4u, REGMAP_LOW_FIRST, REGMAP_PADDING_NUL, text, sizeof text) == 7u && strcmp(text, "AXIS-01") == 0);
    CHECK(regmap_string_from_wire(full, 2u, REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, text, 5u) == 4u && strcmp(text, "ABCD") == 0);
    CHECK(regmap_string_from_wire(high_bytes, 1u, REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, text, sizeof text) == 2u
          && (unsigned char)text[0] == 0xC3u && (unsigned char)text[1] == 0xA9u && text[2] == '\0');

    memset(w, 0xAB, sizeof w);
    CHECK(regmap_string_to_wire("PM-3000", REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, w, 8u) && memcmp(w, model, sizeof model) == 0);
    CHECK(regmap_string_to_wire("AB", REGMAP_HIGH_FIRST, REGMAP_PADDING_SPACE, w, 3u) && memcmp(w, spaced, sizeof spaced) == 0);
    CHECK(regmap_string_to_wire("AXIS-01", REGMAP_LOW_FIRST, REGMAP_PADDING_NUL, w, 4u) && memcmp(w, swapped, sizeof swapped) == 0);
    CHECK(regmap_string_to_wire("ABCD", REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, w, 2u) && w[0] == 0x4142u && w[1] == 0x4344u);
    w[0] = 0x1111u;
    CHECK(!regmap_string_to_wire("ABCDE", REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, w, 2u) && w[0] == 0x1111u); /* too long: untouched */
    CHECK(!regmap_string_to_wire(NULL, REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, w, 2u));
    CHECK(!regmap_string_to_wire("A", REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, NULL, 2u));
    CHECK(regmap_string_to_wire("", REGMAP_HIGH_FIRST, REGMAP_PADDING_SPACE, w, 2u) && w[0] == 0x2020u && w[1] == 0x2020u);
    CHECK(regmap_string_to_wire("", REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, w, 0u));
    for (i = 0u; i < 8u; ++i) {
        w[i] = 0x4141u; /* no NUL anywhere: the reader stops at the register's end */
    }
    CHECK(regmap_string_from_wire(w, 8u, REGMAP_HIGH_FIRST, REGMAP_PADDING_NUL, text, sizeof text) == 16u && strlen(text) == 16u);
}

static void test_firmware_versions(void)
{
    uint32_t version = 0u;
    CHECK(REGMAP_VERSION(2u, 10u) > REGMAP_VERSION(2u, 9u) && REGMAP_VERSION(3u, 0u) > REGMAP_VERSION(2u, 65535u));
    CHECK(regmap_firmware_version(125u, REGMAP_FIRMWARE_DECIMAL, 2u) == REGMAP_VERSION(1u, 25u));
    CHECK(regmap_firmware_version(200u, REGMAP_FIRMWARE_DECIMAL, 2u) == REGMAP_VERSION(2u, 0u));
    CHECK(regmap_firmware_version(7u, REGMAP_FIRMWARE_DECIMAL, 0u) == REGMAP_VERSION(7u, 0u));
    CHECK(regmap_firmware_version(1234u, REGMAP_FIRMWARE_DECIMAL, 1u) == REGMAP_VERSION(123u, 4u));
    CHECK(regmap_firmware_version(0x0203u, REGMAP_FIRMWARE_MAJOR_MINOR, 0u) == REGMAP_VERSION(2u, 3u));
    CHECK(regmap_firmware_version(5u, REGMAP_FIRMWARE_STRING, 0u) == 0u);
    CHECK(regmap_firmware_version(0xFFFFFFFFul, REGMAP_FIRMWARE_DECIMAL, 20u) == REGMAP_VERSION(4u, 294967295ul));
    CHECK(regmap_version_from_text("V2.10 build 7", 14u, &version) && version == REGMAP_VERSION(2u, 10u));
    CHECK(regmap_version_from_text("fw 3", 5u, &version) && version == REGMAP_VERSION(3u, 0u));
    CHECK(regmap_version_from_text("1.2.3", 6u, &version) && version == REGMAP_VERSION(1u, 2u));
    CHECK(regmap_version_from_text("4.", 3u, &version) && version == REGMAP_VERSION(4u, 0u));
    CHECK(regmap_version_from_text("2.10", 3u, &version) && version == REGMAP_VERSION(2u, 1u)); /* only `size` bytes */
    CHECK(!regmap_version_from_text("none", 5u, &version));
    CHECK(!regmap_version_from_text("70000.1", 8u, &version));
    CHECK(!regmap_version_from_text(NULL, 5u, &version));
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
    test_bit_builders();
    test_bit_parsers();
    test_bits();
    test_wire_values();
    test_strings();
    test_firmware_versions();
    test_status_text();
    printf("regmap_rtu.h self-test: %d checks, %d failures\n", checks, failures);
    return failures == 0 ? 0 : 1;
}
