/*
 * A reference codec on libmodbus's own helpers, for tests that check regmap's codecs against an
 * implementation that is not regmap's (tests/support/libmodbus_ref.py drives it).
 *
 *   libmodbus_ref          reads commands on stdin, one a line; answers each with one line, flushed.
 *
 * Commands (numbers are decimal or 0x hex; ORDER is abcd, badc, cdab or dcba):
 *   set_float ORDER VALUE      -> "0xHHHH 0xHHHH"    modbus_set_float_<ORDER>(strtof(VALUE)), the
 *                                                    registers at index 0 then 1
 *   get_float ORDER W0 W1      -> "%.9g 0xXXXXXXXX"  modbus_get_float_<ORDER>({W0, W1}) and the raw
 *                                                    bits of that float (NaN and inf compare exactly)
 *   set_bits N B0 ... B(N-1)   -> "HH HH ..."        N bits (0 or 1) packed 8 at a time with
 *                                                    modbus_get_byte_from_bits: the bytes of a 0x01/0x02
 *                                                    response or a 0x0F request (LSB of the first byte
 *                                                    is the first bit); an empty line for N = 0
 *   get_bits N BYTE0 ...       -> "b b b ..."        the first N bits of the (N+7)/8 bytes, unpacked
 *                                                    with modbus_set_bits_from_bytes
 * Anything else (an unknown command, a bad number, the wrong count) -> "error TEXT"; the next line is
 * read as usual. EOF ends the program.
 */
#include <errno.h>
#include <modbus.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_BITS 2000 /* a 0x01/0x02 response's limit */
#define LINE_ROOM (16 + 2 * MAX_BITS * 6)

typedef void (*set_float_fn)(float, uint16_t *);
typedef float (*get_float_fn)(const uint16_t *);

struct order {
    const char *name;
    set_float_fn set;
    get_float_fn get;
};

static const struct order ORDERS[] = {
    {"abcd", modbus_set_float_abcd, modbus_get_float_abcd},
    {"badc", modbus_set_float_badc, modbus_get_float_badc},
    {"cdab", modbus_set_float_cdab, modbus_get_float_cdab},
    {"dcba", modbus_set_float_dcba, modbus_get_float_dcba},
};

static const struct order *find_order(const char *name) {
    size_t i;
    for (i = 0; name != NULL && i < sizeof ORDERS / sizeof ORDERS[0]; i++) {
        if (strcmp(ORDERS[i].name, name) == 0) {
            return &ORDERS[i];
        }
    }
    return NULL;
}

/* A decimal or 0x-hex number in [0, max]; no octal, no sign, nothing after it. */
static int parse_number(const char *text, unsigned long max, unsigned long *out) {
    char *end = NULL;
    int base = 10;
    if (text == NULL || text[0] < '0' || text[0] > '9') {
        return 0;
    }
    if (text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
        base = 16;
        if (text[2] == '\0') {
            return 0;
        }
    }
    errno = 0;
    *out = strtoul(text, &end, base);
    return errno == 0 && *end == '\0' && *out <= max;
}

static void set_float(void) {
    const struct order *order = find_order(strtok(NULL, " \t"));
    const char *literal = strtok(NULL, " \t");
    char *end = NULL;
    uint16_t words[2];
    float value;
    if (order == NULL || literal == NULL || strtok(NULL, " \t") != NULL) {
        printf("error usage: set_float abcd|badc|cdab|dcba VALUE\n");
        return;
    }
    value = strtof(literal, &end); /* ERANGE is no error here: overflow is inf, underflow subnormal or 0 */
    if (end == literal || *end != '\0') {
        printf("error not a float: %s\n", literal);
        return;
    }
    order->set(value, words);
    printf("0x%04x 0x%04x\n", words[0], words[1]);
}

static void get_float(void) {
    const struct order *order = find_order(strtok(NULL, " \t"));
    unsigned long w0, w1;
    uint16_t words[2];
    uint32_t bits;
    float value;
    if (order == NULL || !parse_number(strtok(NULL, " \t"), 0xFFFF, &w0) || !parse_number(strtok(NULL, " \t"), 0xFFFF, &w1) ||
        strtok(NULL, " \t") != NULL) {
        printf("error usage: get_float abcd|badc|cdab|dcba W0 W1\n");
        return;
    }
    words[0] = (uint16_t)w0;
    words[1] = (uint16_t)w1;
    value = order->get(words);
    memcpy(&bits, &value, sizeof bits);
    printf("%.9g 0x%08lx\n", (double)value, (unsigned long)bits);
}

static void set_bits(void) {
    static uint8_t bits[MAX_BITS];
    unsigned long n, bit, i;
    if (!parse_number(strtok(NULL, " \t"), MAX_BITS, &n)) {
        printf("error usage: set_bits N B0 ... (N at most %d)\n", MAX_BITS);
        return;
    }
    for (i = 0; i < n; i++) {
        if (!parse_number(strtok(NULL, " \t"), 1, &bit)) {
            printf("error bit %lu is missing or not 0 or 1\n", i);
            return;
        }
        bits[i] = (uint8_t)bit;
    }
    if (strtok(NULL, " \t") != NULL) {
        printf("error more than %lu bits\n", n);
        return;
    }
    for (i = 0; i < n; i += 8) {
        printf(i == 0 ? "%02x" : " %02x", modbus_get_byte_from_bits(bits, (int)i, (unsigned)(n - i < 8 ? n - i : 8)));
    }
    printf("\n");
}

static void get_bits(void) {
    static uint8_t bytes[(MAX_BITS + 7) / 8];
    static uint8_t bits[MAX_BITS];
    unsigned long n, byte, i;
    if (!parse_number(strtok(NULL, " \t"), MAX_BITS, &n)) {
        printf("error usage: get_bits N BYTE0 ... (N at most %d)\n", MAX_BITS);
        return;
    }
    for (i = 0; i < (n + 7) / 8; i++) {
        if (!parse_number(strtok(NULL, " \t"), 0xFF, &byte)) {
            printf("error byte %lu is missing or over 0xff\n", i);
            return;
        }
        bytes[i] = (uint8_t)byte;
    }
    if (strtok(NULL, " \t") != NULL) {
        printf("error more than %lu bytes\n", (n + 7) / 8);
        return;
    }
    modbus_set_bits_from_bytes(bits, 0, (unsigned)n, bytes);
    for (i = 0; i < n; i++) {
        printf(i == 0 ? "%u" : " %u", (unsigned)bits[i]);
    }
    printf("\n");
}

int main(void) {
    static char line[LINE_ROOM];
    while (fgets(line, sizeof line, stdin) != NULL) {
        size_t length = strlen(line);
        const char *command;
        if (length > 0 && line[length - 1] == '\n') {
            line[--length] = '\0';
        } else if (!feof(stdin)) {
            int c;
            while ((c = getchar()) != EOF && c != '\n') {
            }
            printf("error line longer than %d characters\n", LINE_ROOM - 2);
            fflush(stdout);
            continue;
        }
        if (length > 0 && line[length - 1] == '\r') {
            line[--length] = '\0';
        }
        command = strtok(line, " \t");
        if (command == NULL) {
            printf("error empty line\n");
        } else if (strcmp(command, "set_float") == 0) {
            set_float();
        } else if (strcmp(command, "get_float") == 0) {
            get_float();
        } else if (strcmp(command, "set_bits") == 0) {
            set_bits();
        } else if (strcmp(command, "get_bits") == 0) {
            get_bits();
        } else {
            printf("error unknown command: %s\n", command);
        }
        fflush(stdout);
    }
    return 0;
}
