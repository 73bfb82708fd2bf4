/*
 * The float and bit helpers of the generated regmap_rtu.h against libmodbus's own, in one program
 * (tests/backends/c/test_c_helpers_against_libmodbus.py builds it with the generated header and libmodbus, and runs it).
 *
 * stdin: one IEEE 754 single's bits a line, as hex (the test gives -0.0, subnormals, infinities,
 * NaNs, 230.1, 3.4e38 and pseudo-random patterns, computed with Python's struct). For each of
 * them and each order (libmodbus's abcd, badc, cdab, dcba = regmap's word order x byte order):
 *   decode: the two registers (bits >> 16, bits & 0xFFFF), and the same with the words exchanged,
 *           read by regmap_f32_from_wire and by modbus_get_float_<order> give the same bits;
 *   encode: the registers regmap_f32_to_wire writes are read back by modbus_get_float_<order>
 *           as the same bits.
 * Then bit packing for every count 1..2000 on pseudo-random bits: regmap_bits_pack equals
 * modbus_get_byte_from_bits byte for byte, and regmap_bits_unpack equals modbus_set_bits_from_bytes.
 * libmodbus 3.1.6's getters read the order they are named after; its setters do not (see
 * tests/support/libmodbus_ref.py), so only the getters are the reference here.
 *
 * Prints a line per mismatch and "N passed, M failed"; the exit status is 0 when none failed.
 */
#include <modbus.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "regmap_rtu.h"

typedef float (*get_float_fn)(const uint16_t *);

struct order {
    const char *name;
    get_float_fn get;
    regmap_word_order word_order;
    regmap_byte_order byte_order;
};

static const struct order ORDERS[] = {
    {"abcd", modbus_get_float_abcd, REGMAP_HIGH_FIRST, REGMAP_HIGH_FIRST},
    {"badc", modbus_get_float_badc, REGMAP_HIGH_FIRST, REGMAP_LOW_FIRST},
    {"cdab", modbus_get_float_cdab, REGMAP_LOW_FIRST, REGMAP_HIGH_FIRST},
    {"dcba", modbus_get_float_dcba, REGMAP_LOW_FIRST, REGMAP_LOW_FIRST},
};

static unsigned long passed;
static unsigned long failed;

static void expect(int ok, const char *what, const char *order, uint32_t bits, uint32_t got, uint32_t want)
{
    if (ok) {
        ++passed;
        return;
    }
    ++failed;
    if (failed <= 50u) {
        printf("FAIL %s %s 0x%08lx: got 0x%08lx, want 0x%08lx\n", what, order, (unsigned long)bits, (unsigned long)got,
               (unsigned long)want);
    }
}

static uint32_t bits_of(float value)
{
    uint32_t bits;
    memcpy(&bits, &value, sizeof bits);
    return bits;
}

static void check_float(uint32_t bits)
{
    size_t i;
    for (i = 0; i < sizeof ORDERS / sizeof ORDERS[0]; i++) {
        const struct order *o = &ORDERS[i];
        uint16_t words[2];
        uint16_t exchanged[2];
        uint32_t ours, theirs;
        words[0] = (uint16_t)(bits >> 16);
        words[1] = (uint16_t)(bits & 0xFFFFu);
        exchanged[0] = words[1];
        exchanged[1] = words[0];
        ours = regmap_f32_to_bits(regmap_f32_from_wire(words, o->word_order, o->byte_order));
        theirs = bits_of(o->get(words));
        expect(ours == theirs, "decode", o->name, bits, ours, theirs);
        ours = regmap_f32_to_bits(regmap_f32_from_wire(exchanged, o->word_order, o->byte_order));
        theirs = bits_of(o->get(exchanged));
        expect(ours == theirs, "decode exchanged", o->name, bits, ours, theirs);
        regmap_f32_to_wire(regmap_f32_from_bits(bits), o->word_order, o->byte_order, words);
        theirs = bits_of(o->get(words));
        expect(theirs == bits, "encode, read back by libmodbus", o->name, bits, theirs, bits);
    }
}

static uint32_t lcg = 12345u;

static uint32_t next_random(void)
{
    lcg = lcg * 1103515245u + 12345u;
    return lcg >> 8;
}

static void check_bits(void)
{
    static uint8_t as_bytes[MODBUS_MAX_READ_BITS];
    static bool bits[MODBUS_MAX_READ_BITS];
    static bool unpacked[MODBUS_MAX_READ_BITS];
    static uint8_t libmodbus_unpacked[MODBUS_MAX_READ_BITS];
    static uint8_t packed[MODBUS_MAX_READ_BITS / 8 + 1];
    unsigned count, i;
    for (count = 1u; count <= MODBUS_MAX_READ_BITS; count++) {
        size_t len = (count + 7u) / 8u;
        int same = 1;
        for (i = 0; i < count; i++) {
            as_bytes[i] = (uint8_t)(next_random() & 1u);
            bits[i] = as_bytes[i] != 0u;
        }
        if (regmap_bits_pack(bits, count, packed, sizeof packed) != len) {
            expect(0, "pack length", "bits", count, (uint32_t)regmap_bits_pack(bits, count, packed, sizeof packed), (uint32_t)len);
            continue;
        }
        for (i = 0; i < count; i += 8u) {
            uint8_t theirs = modbus_get_byte_from_bits(as_bytes, (int)i, count - i < 8u ? count - i : 8u);
            same = same && packed[i / 8u] == theirs;
        }
        expect(same, "pack = modbus_get_byte_from_bits", "bits", count, (uint32_t)same, 1u);
        for (i = 0; i < len; i++) {
            packed[i] = (uint8_t)next_random(); /* padding bits set too: both must ignore them */
        }
        (void)regmap_bits_unpack(packed, count, unpacked);
        modbus_set_bits_from_bytes(libmodbus_unpacked, 0, count, packed);
        same = 1;
        for (i = 0; i < count; i++) {
            same = same && unpacked[i] == (libmodbus_unpacked[i] != 0u);
        }
        expect(same, "unpack = modbus_set_bits_from_bytes", "bits", count, (uint32_t)same, 1u);
    }
}

int main(void)
{
    char line[64];
    unsigned long floats = 0;
    while (fgets(line, sizeof line, stdin) != NULL) {
        char *end = NULL;
        unsigned long bits = strtoul(line, &end, 16);
        if (end == line) {
            printf("error: not hex: %s", line);
            return 2;
        }
        check_float((uint32_t)bits);
        ++floats;
    }
    check_bits();
    printf("%lu floats x 4 orders, bit counts 1..%d\n", floats, MODBUS_MAX_READ_BITS);
    printf("%lu passed, %lu failed\n", passed, failed);
    return failed == 0u ? 0 : 1;
}
