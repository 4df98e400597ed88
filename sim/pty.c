/* pty.c: a pseudo-terminal for a simulated board (see pty.h). */
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <stdint.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>
#include "pty.h"

int pty_open(char *name, size_t n)
{
    struct termios t;
    int m = posix_openpt(O_RDWR | O_NOCTTY), s;
    const char *sn;
    if (m < 0 || grantpt(m) < 0 || unlockpt(m) < 0 || !(sn = ptsname(m))) {
        snprintf(name, n, "no pseudo-terminal: %s", strerror(errno));
        if (m >= 0)
            close(m);
        return -1;
    }
    snprintf(name, n, "%s", sn);
    /* raw: no echo, no CR/LF translation, binary frames pass as they are */
    s = open(sn, O_RDWR | O_NOCTTY);
    if (s < 0 || tcgetattr(s, &t) < 0) {
        snprintf(name, n, "cannot set up %s: %s", sn, strerror(errno));
        close(m);
        return -1;
    }
    cfmakeraw(&t);
    cfsetispeed(&t, B38400);
    cfsetospeed(&t, B38400);
    tcsetattr(s, TCSANOW, &t);
    close(s);
    fcntl(m, F_SETFL, fcntl(m, F_GETFL) | O_NONBLOCK);
    return m;
}

int pty_peer_gone(int fd)
{
    struct pollfd p = { fd, POLLIN, 0 };
    return poll(&p, 1, 0) > 0 && (p.revents & POLLHUP);
}

int pty_wait_peer(int fd, double timeout_s)
{
    struct timespec d = { 0, 20000000 };
    double waited = 0;
    while (pty_peer_gone(fd)) {
        if (waited >= timeout_s)
            return -1;
        nanosleep(&d, NULL);
        waited += 0.02;
    }
    /* a serial library flushes what came in while it set the port up: let it finish */
    d.tv_nsec = 300000000;
    nanosleep(&d, NULL);
    return 0;
}

int pty_write(int fd, const void *buf, size_t n)
{
    const char *p = buf;
    while (n) {
        ssize_t w = write(fd, p, n);
        if (w > 0) {
            p += w;
            n -= (size_t)w;
        } else if (w < 0 && (errno == EAGAIN || errno == EINTR)) {
            struct pollfd q = { fd, POLLOUT, 0 };
            if (poll(&q, 1, 200) > 0 && (q.revents & POLLHUP))
                return -1;
        } else {
            return -1;
        }
    }
    return 0;
}

int pty_drain(int fd, const char *name, double timeout_s)
{
    struct timespec d = { 0, 20000000 };
    double waited = 0;
    int n = 1, s;
    /* what the reader has not taken waits in the slave's input queue: watch it from a
     * second descriptor of the slave (the master has no count of it) */
    s = open(name, O_RDONLY | O_NOCTTY | O_NONBLOCK);
    if (s < 0)
        return -1;
    while (ioctl(s, FIONREAD, &n) == 0 && n > 0 && waited < timeout_s && !pty_peer_gone(fd)) {
        nanosleep(&d, NULL);
        waited += 0.02;
    }
    /* and what is still on its way into that queue */
    d.tv_nsec = 300000000;
    nanosleep(&d, NULL);
    close(s);
    return n > 0 ? -1 : 0;
}

int tty_open(const char *path, char *err, size_t n)
{
    struct termios t;
    int fd = open(path, O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (fd < 0) {
        if (errno == ENOENT)
            snprintf(err, n, "no such port %s (is the adapter plugged in?)", path);
        else if (errno == EACCES)
            snprintf(err, n, "no permission to open %s (add yourself to the dialout group)", path);
        else
            snprintf(err, n, "cannot open %s: %s", path, strerror(errno));
        return -1;
    }
    if (tcgetattr(fd, &t) < 0) {
        snprintf(err, n, "%s is not a serial port: %s", path, strerror(errno));
        close(fd);
        return -1;
    }
    cfmakeraw(&t);
    cfsetispeed(&t, B38400);
    cfsetospeed(&t, B38400);
    t.c_cflag |= CLOCAL | CREAD;
    tcsetattr(fd, TCSANOW, &t);
    tcflush(fd, TCIOFLUSH);
    return fd;
}

int link_read(int fd, uint8_t *buf, size_t n, double timeout_s)
{
    struct pollfd p = { fd, POLLIN, 0 };
    ssize_t got;
    if (poll(&p, 1, (int)(timeout_s * 1000)) <= 0)
        return 0;
    got = read(fd, buf, n);
    if (got < 0)
        return (errno == EAGAIN || errno == EINTR) ? 0 : -1;
    return got == 0 && (p.revents & POLLHUP) ? -1 : (int)got;
}
