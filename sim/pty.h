/* pty.h: a pseudo-terminal for a simulated board: the PC's tools open its other end like a serial port. */
#ifndef SIM_PTY_H
#define SIM_PTY_H

#include <stddef.h>
#include <stdint.h>

/* Open a pseudo-terminal pair in raw mode; returns the master's descriptor (non-blocking reads)
 * and the slave's path in name, or -1 with the reason in name. */
int pty_open(char *name, size_t n);
/* Wait until a program has opened the slave (up to timeout_s); 0 when one has, -1 on timeout. */
int pty_wait_peer(int fd, double timeout_s);
/* 1 when nobody holds the slave open any more. */
int pty_peer_gone(int fd);
/* Write all of buf (blocks while the reader is behind); -1 when the peer went away. */
int pty_write(int fd, const void *buf, size_t n);

/* Wait (up to timeout_s) until the reader has taken everything written: closing the master
 * drops what is still queued. -1 when some is left. */
int pty_drain(int fd, const char *name, double timeout_s);

/* A serial port (or a pseudo-terminal's slave) in raw mode at 38400 8N1, non-blocking; -1 and
 * why in err (no such port, no permission...). */
int tty_open(const char *path, char *err, size_t n);
/* Up to n bytes within timeout_s: the count (0: none came), -1 when the other end is gone. */
int link_read(int fd, uint8_t *buf, size_t n, double timeout_s);

#endif
