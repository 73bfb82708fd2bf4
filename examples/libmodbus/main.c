/*
 * Read a Leadshine iDM-RS over RS-485 with libmodbus, using the macros of the generated
 * generated/c/idm_rs.h: serial settings, register addresses, word counts, scale, bitfields,
 * 32-bit word order and the read plan. Usage: ./read_idm_rs [serial-device] [slave-id]
 *
 * Build (see README.md):
 *   cc -std=c99 -Wall -Wextra -I../../generated/c $(pkg-config --cflags libmodbus) main.c \
 *      $(pkg-config --libs libmodbus) -o read_idm_rs
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

#include <modbus.h>

/* This file defines the header's tables (the read plan); other files of a program include it without the macro. */
#define IDM_RS_IMPLEMENTATION
#include "idm_rs.h"

static int read_words(modbus_t *ctx, uint16_t address, uint16_t count, uint16_t *words)
{
    if (modbus_read_registers(ctx, address, count, words) != count) {
        fprintf(stderr, "read of %u register(s) at 0x%04X failed: %s\n", (unsigned)count, (unsigned)address, modbus_strerror(errno));
        return -1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *port = argc > 1 ? argv[1] : "/dev/ttyUSB0";
    int slave = argc > 2 ? atoi(argv[2]) : 1;
    uint16_t words[IDM_RS_MAX_READ_REGISTERS];
    unsigned long readable = 0;
    size_t i;
    modbus_t *ctx;

    if (slave < (int)IDM_RS_SLAVE_MIN || slave > (int)IDM_RS_SLAVE_MAX) {
        fprintf(stderr, "slave id must be %u..%u\n", IDM_RS_SLAVE_MIN, IDM_RS_SLAVE_MAX);
        return 2;
    }
    ctx = modbus_new_rtu(port, (int)IDM_RS_DEFAULT_BAUD, IDM_RS_PARITY, (int)IDM_RS_DATA_BITS, (int)IDM_RS_STOP_BITS);
    if (ctx == NULL || modbus_set_slave(ctx, slave) != 0 || modbus_connect(ctx) != 0) {
        fprintf(stderr, "cannot open %s: %s\n", port, modbus_strerror(errno));
        modbus_free(ctx);
        return 1;
    }
    printf("iDM-RS map %s on %s, slave %d\n", IDM_RS_MAP_VERSION, port, slave);

    /* Pr5.00 peak current: a paired parameter, read alone at its listed (low word) address.
     * value = raw x SCALE; SCALE_NUM / SCALE_DEN give the same without floating point. */
    if (read_words(ctx, IDM_RS_PEAK_CURRENT_ADDR, IDM_RS_PEAK_CURRENT_WORDS, words) == 0) {
        long milliamps = (long)words[0] * IDM_RS_PEAK_CURRENT_SCALE_NUM * 1000L / IDM_RS_PEAK_CURRENT_SCALE_DEN;
        printf("peak current: %.2f A = %ld mA (raw %u)\n", (double)((float)words[0] * IDM_RS_PEAK_CURRENT_SCALE), milliamps, (unsigned)words[0]);
    }

    /* Run status: one word of flags, decoded with the generated bitfield getters. */
    if (read_words(ctx, IDM_RS_RUN_STATUS_ADDR, IDM_RS_RUN_STATUS_WORDS, words) == 0) {
        printf("status: fault=%u enabled=%u running=%u path done=%u homing done=%u\n", (unsigned)idm_rs_run_status_get_fault(words[0]),
               (unsigned)idm_rs_run_status_get_enabled(words[0]), (unsigned)idm_rs_run_status_get_running(words[0]),
               (unsigned)idm_rs_run_status_get_path_done(words[0]), (unsigned)idm_rs_run_status_get_homing_done(words[0]));
    }

    /* Pr8.44 motor position: a signed 32-bit value in the register's word order. */
    if (read_words(ctx, IDM_RS_MOTOR_POSITION_ADDR, IDM_RS_MOTOR_POSITION_WORDS, words) == 0) {
        printf("motor position: %ld pulses\n", (long)regmap_s32_from_words(words, IDM_RS_MOTOR_POSITION_WORD_ORDER));
    }

    /* Every readable register, in the fewest requests the drive accepts (the Python client's read_all plan). */
    for (i = 0; i < IDM_RS_READ_PLAN_LEN; ++i) {
        if (read_words(ctx, idm_rs_read_plan[i].address, idm_rs_read_plan[i].count, words) != 0) {
            break;
        }
        readable += idm_rs_read_plan[i].count;
    }
    printf("read plan: %u requests, %lu words read\n", (unsigned)IDM_RS_READ_PLAN_LEN, readable);

    modbus_close(ctx);
    modbus_free(ctx);
    return 0;
}
