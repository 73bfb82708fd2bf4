/*
 * Load generator for the simulator bench: CLIENTS threads, each its own libmodbus TCP connection,
 * each sending REQUESTS reads of COUNT registers at ADDRESS, one at a time (send, wait, next).
 *   modbus_load PORT CLIENTS REQUESTS ADDRESS COUNT
 * Prints one line: "requests N errors E seconds S p50_us P p99_us Q".
 */
#include <errno.h>
#include <modbus.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

struct job {
    int port, requests, address, count, errors;
    double *latency_us;
};

static double now_s(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec / 1e9;
}

static void *client(void *arg) {
    struct job *job = arg;
    modbus_t *ctx = modbus_new_tcp("127.0.0.1", job->port);
    uint16_t words[MODBUS_MAX_READ_REGISTERS];
    modbus_set_response_timeout(ctx, 5, 0);
    if (ctx == NULL || modbus_set_slave(ctx, 1) != 0 || modbus_connect(ctx) != 0) {
        job->errors = job->requests;
        return NULL;
    }
    for (int i = 0; i < job->requests; i++) {
        double start = now_s();
        if (modbus_read_registers(ctx, job->address, job->count, words) != job->count) {
            job->errors++;
        }
        job->latency_us[i] = (now_s() - start) * 1e6;
    }
    modbus_close(ctx);
    modbus_free(ctx);
    return NULL;
}

static int by_value(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv) {
    if (argc != 6) {
        fprintf(stderr, "usage: modbus_load PORT CLIENTS REQUESTS ADDRESS COUNT\n");
        return 2;
    }
    int port = atoi(argv[1]), clients = atoi(argv[2]), requests = atoi(argv[3]);
    int address = (int)strtol(argv[4], NULL, 0), count = atoi(argv[5]);
    if (clients < 1 || clients > 1000 || requests < 1 || count < 1 || count > MODBUS_MAX_READ_REGISTERS) {
        fprintf(stderr, "modbus_load: argument out of range\n");
        return 2;
    }
    double *latency = calloc((size_t)clients * (size_t)requests, sizeof *latency);
    struct job *jobs = calloc((size_t)clients, sizeof *jobs);
    pthread_t *threads = calloc((size_t)clients, sizeof *threads);
    if (latency == NULL || jobs == NULL || threads == NULL) {
        return 2;
    }
    double start = now_s();
    for (int c = 0; c < clients; c++) {
        jobs[c] = (struct job){port, requests, address, count, 0, latency + (size_t)c * (size_t)requests};
        pthread_create(&threads[c], NULL, client, &jobs[c]);
    }
    int errors = 0;
    for (int c = 0; c < clients; c++) {
        pthread_join(threads[c], NULL);
        errors += jobs[c].errors;
    }
    double seconds = now_s() - start;
    size_t total = (size_t)clients * (size_t)requests;
    qsort(latency, total, sizeof *latency, by_value);
    printf("requests %zu errors %d seconds %.6f p50_us %.1f p99_us %.1f\n", total, errors, seconds, latency[total / 2],
           latency[(total * 99) / 100]);
    free(latency);
    free(jobs);
    free(threads);
    return 0;
}
