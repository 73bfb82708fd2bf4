/*
 * A reference Modbus TCP server on libmodbus, its four tables loaded from a file, for tests that check
 * regmap's clients against a server that is not regmap's (tests/support/libmodbus_ref.py drives it).
 *
 *   libmodbus_tables_server PORT TABLES
 *
 * TABLES has one entry a line, `#` starts a comment, numbers are decimal or 0x hex:
 *   coil ADDR 0|1    discrete_input ADDR 0|1    holding ADDR WORD    input ADDR WORD
 * Each table spans the lowest to the highest address it names (addresses in between are 0); a table
 * the file does not name spans 0..15, all 0. An address named twice is an error.
 *
 * It listens on 127.0.0.1:PORT (PORT 0: a free port the kernel picks), prints "listening PORT" with
 * the port it got and flushes, then answers any number of clients, one after the other or at once,
 * with modbus_receive / modbus_reply (libmodbus's own checks: exception 0x02 outside a table).
 *
 * The dump: it prints every table, one "SPACE ADDR VALUE" line for each address (SPACE as in TABLES,
 * coils then discrete inputs, holding then input registers, addresses ascending, values decimal) and
 * exits 0 when
 *   - a line "dump" arrives on stdin, or stdin reaches EOF (so it never outlives the test that
 *     started it with a pipe: closing the pipe is enough), or
 *   - it gets SIGTERM or SIGINT (blocked except while it waits in pselect, so no signal is lost
 *     and none cuts a request in half).
 * A request whose reply was sent has been applied, so a dump after a client saw its replies holds
 * every write. Errors go to stderr, with exit status 2.
 */
#define _POSIX_C_SOURCE 200112L

#include <errno.h>
#include <modbus.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#define DEFAULT_COUNT 16
#define MAX_ENTRIES 0x10000

enum { COIL, DISCRETE_INPUT, HOLDING, INPUT, SPACES };
static const char *const SPACE_NAMES[SPACES] = {"coil", "discrete_input", "holding", "input"};
static const unsigned long SPACE_MAX[SPACES] = {1, 1, 0xFFFF, 0xFFFF};

struct entry {
    unsigned address;
    unsigned value;
};

struct table {
    struct entry *entries;
    size_t count;
    unsigned first, last;
};

static volatile sig_atomic_t stop_signal = 0;

static void on_signal(int signal_number) { stop_signal = signal_number; }

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

static int load(const char *path, struct table tables[SPACES]) {
    char line[512];
    unsigned line_number = 0;
    int space;
    FILE *file = fopen(path, "r");
    if (file == NULL) {
        fprintf(stderr, "cannot open %s: %s\n", path, strerror(errno));
        return 0;
    }
    for (space = 0; space < SPACES; space++) {
        tables[space].entries = malloc(MAX_ENTRIES * sizeof(struct entry));
        tables[space].count = 0;
        if (tables[space].entries == NULL) {
            fprintf(stderr, "out of memory\n");
            fclose(file);
            return 0;
        }
    }
    while (fgets(line, sizeof line, file) != NULL) {
        char *hash = strchr(line, '#');
        const char *name, *address_text, *value_text;
        unsigned long address, value;
        struct table *table;
        size_t i;
        line_number++;
        if (hash != NULL) {
            *hash = '\0';
        }
        name = strtok(line, " \t\r\n");
        if (name == NULL) {
            continue;
        }
        address_text = strtok(NULL, " \t\r\n");
        value_text = strtok(NULL, " \t\r\n");
        for (space = 0; space < SPACES && strcmp(name, SPACE_NAMES[space]) != 0; space++) {
        }
        if (space == SPACES || !parse_number(address_text, 0xFFFF, &address) || !parse_number(value_text, SPACE_MAX[space], &value) ||
            strtok(NULL, " \t\r\n") != NULL) {
            fprintf(stderr, "%s:%u: expected coil|discrete_input ADDR 0|1 or holding|input ADDR WORD\n", path, line_number);
            fclose(file);
            return 0;
        }
        table = &tables[space];
        for (i = 0; i < table->count; i++) {
            if (table->entries[i].address == address) {
                fprintf(stderr, "%s:%u: %s %lu is named twice\n", path, line_number, name, address);
                fclose(file);
                return 0;
            }
        }
        table->entries[table->count].address = (unsigned)address;
        table->entries[table->count].value = (unsigned)value;
        if (table->count == 0 || address < table->first) {
            table->first = (unsigned)address;
        }
        if (table->count == 0 || address > table->last) {
            table->last = (unsigned)address;
        }
        table->count++;
    }
    fclose(file);
    for (space = 0; space < SPACES; space++) {
        if (tables[space].count == 0) {
            tables[space].first = 0;
            tables[space].last = DEFAULT_COUNT - 1;
        }
    }
    return 1;
}

static modbus_mapping_t *make_mapping(const struct table tables[SPACES]) {
    modbus_mapping_t *map = modbus_mapping_new_start_address(
        tables[COIL].first, tables[COIL].last - tables[COIL].first + 1, tables[DISCRETE_INPUT].first,
        tables[DISCRETE_INPUT].last - tables[DISCRETE_INPUT].first + 1, tables[HOLDING].first, tables[HOLDING].last - tables[HOLDING].first + 1,
        tables[INPUT].first, tables[INPUT].last - tables[INPUT].first + 1);
    size_t i;
    if (map == NULL) {
        return NULL;
    }
    for (i = 0; i < tables[COIL].count; i++) {
        map->tab_bits[tables[COIL].entries[i].address - map->start_bits] = (uint8_t)tables[COIL].entries[i].value;
    }
    for (i = 0; i < tables[DISCRETE_INPUT].count; i++) {
        map->tab_input_bits[tables[DISCRETE_INPUT].entries[i].address - map->start_input_bits] = (uint8_t)tables[DISCRETE_INPUT].entries[i].value;
    }
    for (i = 0; i < tables[HOLDING].count; i++) {
        map->tab_registers[tables[HOLDING].entries[i].address - map->start_registers] = (uint16_t)tables[HOLDING].entries[i].value;
    }
    for (i = 0; i < tables[INPUT].count; i++) {
        map->tab_input_registers[tables[INPUT].entries[i].address - map->start_input_registers] = (uint16_t)tables[INPUT].entries[i].value;
    }
    return map;
}

static void dump(const modbus_mapping_t *map) {
    int i;
    for (i = 0; i < map->nb_bits; i++) {
        printf("coil %d %u\n", map->start_bits + i, (unsigned)map->tab_bits[i]);
    }
    for (i = 0; i < map->nb_input_bits; i++) {
        printf("discrete_input %d %u\n", map->start_input_bits + i, (unsigned)map->tab_input_bits[i]);
    }
    for (i = 0; i < map->nb_registers; i++) {
        printf("holding %d %u\n", map->start_registers + i, (unsigned)map->tab_registers[i]);
    }
    for (i = 0; i < map->nb_input_registers; i++) {
        printf("input %d %u\n", map->start_input_registers + i, (unsigned)map->tab_input_registers[i]);
    }
    fflush(stdout);
}

/* Reads what stdin has; 1 once a "dump" line or EOF arrived. Other lines are ignored (with a note). */
static int stdin_says_dump(void) {
    static char pending[256];
    static size_t used = 0;
    char chunk[256];
    ssize_t n = read(STDIN_FILENO, chunk, sizeof chunk);
    ssize_t i;
    if (n <= 0) {
        return n == 0 || errno != EINTR; /* EOF, or stdin is unusable */
    }
    for (i = 0; i < n; i++) {
        if (chunk[i] != '\n') {
            if (used < sizeof pending - 1) {
                pending[used++] = chunk[i];
            }
            continue;
        }
        if (used > 0 && pending[used - 1] == '\r') {
            used--;
        }
        pending[used] = '\0';
        used = 0;
        if (strcmp(pending, "dump") == 0) {
            return 1;
        }
        fprintf(stderr, "ignored on stdin: %s\n", pending);
    }
    return 0;
}

int main(int argc, char **argv) {
    struct table tables[SPACES];
    struct sigaction action;
    struct sockaddr_in bound;
    socklen_t bound_length = sizeof bound;
    sigset_t blocked, waiting;
    uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
    unsigned long port;
    modbus_t *ctx;
    modbus_mapping_t *map;
    fd_set all;
    int listener, highest, space;

    if (argc != 3 || !parse_number(argv[1], 0xFFFF, &port)) {
        fprintf(stderr, "usage: libmodbus_tables_server PORT TABLES\n");
        return 2;
    }
    if (!load(argv[2], tables)) {
        return 2;
    }
    map = make_mapping(tables);
    for (space = 0; space < SPACES; space++) {
        free(tables[space].entries);
    }
    ctx = modbus_new_tcp("127.0.0.1", (int)port);
    if (ctx == NULL || map == NULL) {
        fprintf(stderr, "cannot set up libmodbus: %s\n", modbus_strerror(errno));
        return 2;
    }

    memset(&action, 0, sizeof action);
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    sigemptyset(&blocked);
    sigaddset(&blocked, SIGTERM);
    sigaddset(&blocked, SIGINT);
    if (sigprocmask(SIG_BLOCK, &blocked, &waiting) != 0 || sigaction(SIGTERM, &action, NULL) != 0 || sigaction(SIGINT, &action, NULL) != 0) {
        fprintf(stderr, "cannot set up signals: %s\n", strerror(errno));
        return 2;
    }
    sigdelset(&waiting, SIGTERM);
    sigdelset(&waiting, SIGINT);

    listener = modbus_tcp_listen(ctx, 16);
    if (listener < 0 || getsockname(listener, (struct sockaddr *)&bound, &bound_length) != 0) {
        fprintf(stderr, "cannot listen on 127.0.0.1:%lu: %s\n", port, modbus_strerror(errno));
        return 2;
    }
    printf("listening %u\n", (unsigned)ntohs(bound.sin_port));
    fflush(stdout);

    FD_ZERO(&all);
    FD_SET(listener, &all);
    FD_SET(STDIN_FILENO, &all);
    highest = listener > STDIN_FILENO ? listener : STDIN_FILENO;
    for (;;) {
        fd_set ready = all;
        int fd;
        if (pselect(highest + 1, &ready, NULL, NULL, NULL, &waiting) < 0) {
            if (errno == EINTR && stop_signal != 0) {
                break;
            }
            if (errno == EINTR) {
                continue;
            }
            fprintf(stderr, "select: %s\n", strerror(errno));
            return 1;
        }
        if (FD_ISSET(STDIN_FILENO, &ready) && stdin_says_dump()) {
            break;
        }
        for (fd = 0; fd <= highest; fd++) {
            if (fd == STDIN_FILENO || !FD_ISSET(fd, &ready)) {
                continue;
            }
            if (fd == listener) {
                int client = modbus_tcp_accept(ctx, &listener);
                if (client >= 0 && client < FD_SETSIZE) {
                    FD_SET(client, &all);
                    highest = client > highest ? client : highest;
                } else if (client >= 0) {
                    close(client);
                }
                continue;
            }
            modbus_set_socket(ctx, fd);
            {
                int n = modbus_receive(ctx, query);
                if (n > 0) {
                    modbus_reply(ctx, query, n, map);
                } else if (n < 0) {
                    close(fd);
                    FD_CLR(fd, &all);
                }
            }
        }
    }
    dump(map);
    modbus_mapping_free(map);
    modbus_set_socket(ctx, -1);
    modbus_free(ctx);
    close(listener);
    return 0;
}
