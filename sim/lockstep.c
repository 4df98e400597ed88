/* lockstep.c: a firmware in s51 in lock step with the host's plant: the s51 process, its two FIFOs, its console, the frames' bytes. */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include "lockstep.h"
#include "hal_host.h"

void lockstep_init(lockstep_t *l)
{
    memset(l, 0, sizeof *l);
    l->pid = -1;
    l->to_s51 = l->from_s51 = l->console = -1;
}

int lockstep_fifos(lockstep_t *l, const char *tmpl, char *err, size_t n)
{
    snprintf(l->dir, sizeof l->dir, "%s", tmpl);
    if (!mkdtemp(l->dir)) {
        snprintf(err, n, "mkdtemp: %s", strerror(errno));
        l->dir[0] = 0;
        return -1;
    }
    snprintf(l->fifo_in, sizeof l->fifo_in, "%s/to_s51", l->dir);
    snprintf(l->fifo_out, sizeof l->fifo_out, "%s/from_s51", l->dir);
    if (mkfifo(l->fifo_in, 0600) < 0 || mkfifo(l->fifo_out, 0600) < 0) {
        snprintf(err, n, "fifo: %s", strerror(errno));
        return -1;
    }
    return 0;
}

int lockstep_spawn(lockstep_t *l, char *const argv[], int env_link)
{
    int cons[2];
    if (pipe(cons) < 0)
        return -1;
    l->pid = fork();
    if (l->pid == 0) {
        char log[96];
        int fd;
        snprintf(log, sizeof log, "%s/s51.log", l->dir);
        fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0600);
        dup2(cons[0], 0);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
        }
        close(cons[1]);
        if (env_link) {
            setenv("STC12_LINK_IN", l->fifo_in, 1);
            setenv("STC12_LINK_OUT", l->fifo_out, 1);
        }
        execvp(argv[0], argv);
        _exit(127);
    }
    close(cons[0]);
    l->console = cons[1];
    if (l->pid < 0)
        return -1;
    l->to_s51 = open(l->fifo_in, O_WRONLY);
    l->from_s51 = l->to_s51 >= 0 ? open(l->fifo_out, O_RDONLY) : -1;
    if (l->from_s51 < 0 || write(l->console, "run\n", 4) != 4)
        return -1;
    return 0;
}

void lockstep_erase_eeprom(void)
{
    memset(hal_host_eeprom(), 0xFF, HAL_EEPROM_SIZE);
    hal_host_eeprom_cut_after(-1);
}

void lockstep_drop_uart(void)
{
    while (hal_host_uart_tx_pop() >= 0)
        ;
}

void lockstep_write(lockstep_t *l, const uint8_t *b, size_t n)
{
    while (n && !l->failed) {
        ssize_t w = write(l->to_s51, b, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            l->failed = 1;
            return;
        }
        b += w;
        n -= (size_t)w;
    }
}

int lockstep_byte(lockstep_t *l)
{
    if (l->failed)
        return -1;
    if (l->i_buf == l->n_buf) {
        ssize_t r;
        do
            r = read(l->from_s51, l->buf, sizeof l->buf);
        while (r < 0 && errno == EINTR);
        if (r <= 0) {
            l->failed = 1;
            return -1;
        }
        l->n_buf = (size_t)r;
        l->i_buf = 0;
    }
    return l->buf[l->i_buf++];
}

int lockstep_read(lockstep_t *l, uint8_t *b, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) {
        int c = lockstep_byte(l);
        if (c < 0) {
            memset(b, 0, n);
            return -1;
        }
        b[i] = (uint8_t)c;
    }
    return 0;
}

size_t lockstep_put(uint8_t *b, uint64_t v, int n)
{
    int i;
    for (i = 0; i < n; i++)
        b[i] = (uint8_t)(v >> (8 * i));
    return (size_t)n;
}

uint64_t lockstep_get(const uint8_t *b, int n)
{
    uint64_t v = 0;
    int i;
    for (i = 0; i < n; i++)
        v |= (uint64_t)b[i] << (8 * i);
    return v;
}

unsigned lockstep_u16(lockstep_t *l)
{
    uint8_t b[2];
    lockstep_read(l, b, 2);
    return (unsigned)lockstep_get(b, 2);
}

int lockstep_wait(lockstep_t *l, int exit_any)
{
    int st = 0;
    if (l->pid <= 0)
        return -1;
    waitpid(l->pid, &st, 0);
    l->pid = -1;
    return WIFEXITED(st) && (exit_any || WEXITSTATUS(st) == 0) ? 0 : -1;
}

void lockstep_close(lockstep_t *l)
{
    char f[128];
    if (l->console >= 0)
        close(l->console);
    l->console = -1;
    if (l->pid > 0) {
        kill(l->pid, SIGTERM);
        waitpid(l->pid, NULL, 0);
        l->pid = -1;
    }
    if (l->to_s51 >= 0)
        close(l->to_s51);
    if (l->from_s51 >= 0)
        close(l->from_s51);
    l->to_s51 = l->from_s51 = -1;
    if (!l->dir[0])
        return;
    unlink(l->fifo_in);
    unlink(l->fifo_out);
    snprintf(f, sizeof f, "%s/s51.log", l->dir);
    unlink(f);
    rmdir(l->dir);
    l->dir[0] = 0;
}

int lockstep_grow(void **a, size_t *cap, size_t n, size_t size)
{
    void *p;
    if (n < *cap)
        return 0;
    p = realloc(*a, (*cap ? 2 * *cap : 65536) * size);
    if (!p)
        return -1;
    *a = p;
    *cap = *cap ? 2 * *cap : 65536;
    return 0;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

uint32_t *lockstep_sorted_u32(const uint32_t *v, size_t n)
{
    uint32_t *s = malloc((n ? n : 1) * sizeof *s);
    if (!s)
        return NULL;
    memcpy(s, v, n * sizeof *s);
    qsort(s, n, sizeof *s, cmp_u32);
    return s;
}
