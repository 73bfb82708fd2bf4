/*
 * An independent Modbus master for the simulator's conformance tests, on libmodbus.
 *
 *   sim_client tcp HOST PORT SLAVE OP...
 *   sim_client rtu DEVICE BAUD SLAVE OP...
 *
 * OPs, each answered by one output line:
 *   read ADDR COUNT        -> "ok W W ..." | "exception CODE" | "error TEXT"
 *   write ADDR W[,W...]    -> "ok N"       | "exception CODE" | "error TEXT"   (function 0x10)
 *   write1 ADDR W          -> "ok 1"       | ...                              (function 0x06)
 *   raw HEX                -> "raw HEX"    | "error TEXT"   HEX is slave id + PDU, e.g. 0103019100ff;
 *                             libmodbus adds the MBAP header or the CRC and parses the answer, printed
 *                             as slave id + PDU too.
 * Numbers are C literals (0x0191 or 401). libmodbus refuses counts over 125 itself: use raw for those.
 */
#include <errno.h>
#include <modbus.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void report_error(void) {
    if (errno > MODBUS_ENOBASE && errno < MODBUS_ENOBASE + 0x20) {
        printf("exception %d\n", errno - MODBUS_ENOBASE);
    } else {
        printf("error %s\n", modbus_strerror(errno));
    }
}

static int hex_bytes(const char *text, uint8_t *out, int room) {
    int n = 0;
    size_t len = strlen(text);
    if (len % 2 != 0) {
        return -1;
    }
    for (size_t i = 0; i < len && n < room; i += 2) {
        char pair[3] = {text[i], text[i + 1], 0};
        out[n++] = (uint8_t)strtoul(pair, NULL, 16);
    }
    return n;
}

int main(int argc, char **argv) {
    if (argc < 5) {
        fprintf(stderr, "usage: sim_client tcp HOST PORT SLAVE OP... | rtu DEVICE BAUD SLAVE OP...\n");
        return 2;
    }
    modbus_t *ctx;
    if (strcmp(argv[1], "tcp") == 0) {
        ctx = modbus_new_tcp(argv[2], atoi(argv[3]));
    } else {
        ctx = modbus_new_rtu(argv[2], atoi(argv[3]), 'N', 8, 1);
    }
    if (ctx == NULL || modbus_set_slave(ctx, atoi(argv[4])) != 0) {
        fprintf(stderr, "cannot set up libmodbus: %s\n", modbus_strerror(errno));
        return 2;
    }
    modbus_set_response_timeout(ctx, 0, 500000);
    if (modbus_connect(ctx) != 0) {
        fprintf(stderr, "cannot connect: %s\n", modbus_strerror(errno));
        modbus_free(ctx);
        return 3;
    }
    for (int i = 5; i < argc; i++) {
        const char *op = argv[i];
        if (strcmp(op, "read") == 0 && i + 2 < argc) {
            int address = (int)strtol(argv[i + 1], NULL, 0), count = (int)strtol(argv[i + 2], NULL, 0);
            uint16_t words[MODBUS_MAX_READ_REGISTERS];
            i += 2;
            int got = count > MODBUS_MAX_READ_REGISTERS ? -1 : modbus_read_registers(ctx, address, count, words);
            if (count > MODBUS_MAX_READ_REGISTERS) {
                errno = EMBMDATA;
            }
            if (got < 0) {
                report_error();
                modbus_flush(ctx);
                continue;
            }
            printf("ok");
            for (int k = 0; k < got; k++) {
                printf(" %u", words[k]);
            }
            printf("\n");
        } else if ((strcmp(op, "write") == 0 || strcmp(op, "write1") == 0) && i + 2 < argc) {
            int address = (int)strtol(argv[i + 1], NULL, 0);
            uint16_t words[MODBUS_MAX_WRITE_REGISTERS];
            int n = 0;
            char *list = strdup(argv[i + 2]);
            for (char *item = strtok(list, ","); item != NULL && n < MODBUS_MAX_WRITE_REGISTERS; item = strtok(NULL, ",")) {
                words[n++] = (uint16_t)strtol(item, NULL, 0);
            }
            free(list);
            i += 2;
            int done = strcmp(op, "write1") == 0 ? modbus_write_register(ctx, address, words[0]) : modbus_write_registers(ctx, address, n, words);
            if (done < 0) {
                report_error();
                modbus_flush(ctx);
            } else {
                printf("ok %d\n", done);
            }
        } else if (strcmp(op, "raw") == 0 && i + 1 < argc) {
            uint8_t request[MODBUS_MAX_ADU_LENGTH], answer[MODBUS_MAX_ADU_LENGTH];
            int n = hex_bytes(argv[++i], request, (int)sizeof request);
            if (n < 2 || modbus_send_raw_request(ctx, request, n) < 0) {
                report_error();
                continue;
            }
            int got = modbus_receive_confirmation(ctx, answer);
            if (got < 0) {
                report_error();
                modbus_flush(ctx);
                continue;
            }
            /* From the slave id to the end of the PDU: the same on TCP (MBAP header dropped) and RTU (CRC,
               already checked by libmodbus, dropped). */
            int header = modbus_get_header_length(ctx), end = strcmp(argv[1], "tcp") == 0 ? got : got - 2;
            printf("raw ");
            for (int k = header - 1; k < end; k++) {
                printf("%02x", answer[k]);
            }
            printf("\n");
        } else {
            fprintf(stderr, "bad operation %s\n", op);
            modbus_close(ctx);
            modbus_free(ctx);
            return 2;
        }
        fflush(stdout);
    }
    modbus_close(ctx);
    modbus_free(ctx);
    return 0;
}
