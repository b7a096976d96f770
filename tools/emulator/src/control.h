/* A UNIX-socket control channel: one text command per line, one reply line each. */
#ifndef OF_EMU_CONTROL_H
#define OF_EMU_CONTROL_H

#include <stddef.h>

#define CONTROL_MAX_CLIENTS 8
#define CONTROL_LINE 1024

/* Executes one command line; writes the reply (without newline) into reply. */
typedef void (*control_handler_t)(void *ctx, char *line, char *reply, size_t replylen);

typedef struct {
    int listen_fd;
    char path[108];
    int fds[CONTROL_MAX_CLIENTS];
    char buf[CONTROL_MAX_CLIENTS][CONTROL_LINE];
    size_t len[CONTROL_MAX_CLIENTS];
    control_handler_t handler;
    void *ctx;
} control_t;

/* Listen on path; a stale socket there is replaced, anything else (a file, a live
 * emulator's socket) is refused. Returns -1 with a message in err. */
int control_open(control_t *c, const char *path, control_handler_t h, void *ctx, char *err,
                 size_t errlen);
/* Accept clients and run complete command lines; never blocks. */
void control_service(control_t *c);
/* File descriptors to wait on (listen socket and clients); returns how many. */
int control_fds(const control_t *c, int *fds, int max);
void control_close(control_t *c);

#endif
