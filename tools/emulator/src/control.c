/* Non-blocking line server. Replies are short, so a blocking send is never needed; a
 * client that stops reading is dropped rather than stalling the simulation. */
#include "control.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

int control_open(control_t *c, const char *path, control_handler_t h, void *ctx, char *err,
                 size_t errlen)
{
    c->listen_fd = -1;
    c->handler = h;
    c->ctx = ctx;
    for (int i = 0; i < CONTROL_MAX_CLIENTS; i++) {
        c->fds[i] = -1;
        c->len[i] = 0;
    }
    struct sockaddr_un a;
    memset(&a, 0, sizeof a);
    a.sun_family = AF_UNIX;
    if (strlen(path) >= sizeof a.sun_path) {
        snprintf(err, errlen, "control socket path too long (max %zu bytes): %s",
                 sizeof a.sun_path - 1, path);
        return -1;
    }
    snprintf(a.sun_path, sizeof a.sun_path, "%s", path);
    snprintf(c->path, sizeof c->path, "%s", path);
    int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    if (fd < 0) {
        snprintf(err, errlen, "socket: %s", strerror(errno));
        return -1;
    }
    /* Only a stale socket of ours is replaced: never a user's file (a mistyped --control
     * must not delete it), nor the socket of an emulator that is still running. */
    struct stat st;
    if (lstat(path, &st) == 0) {
        if (!S_ISSOCK(st.st_mode)) {
            snprintf(err, errlen,
                     "cannot listen on %s: it exists and is not a socket; give a new path "
                     "for --control (the file is left as it is)",
                     path);
            close(fd);
            return -1;
        }
        if (connect(fd, (struct sockaddr *)&a, sizeof a) == 0) {
            snprintf(err, errlen,
                     "cannot listen on %s: another emulator is listening there; give another "
                     "path for --control",
                     path);
            close(fd);
            return -1;
        }
        close(fd);
        fd = socket(AF_UNIX, SOCK_STREAM, 0); /* a failed connect leaves fd unusable */
        if (fd < 0) {
            snprintf(err, errlen, "socket: %s", strerror(errno));
            return -1;
        }
        unlink(path);
    }
    if (bind(fd, (struct sockaddr *)&a, sizeof a) || listen(fd, 4)) {
        snprintf(err, errlen, "cannot listen on %s: %s", path, strerror(errno));
        close(fd);
        return -1;
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    c->listen_fd = fd;
    return 0;
}

static void drop_client(control_t *c, int i)
{
    close(c->fds[i]);
    c->fds[i] = -1;
    c->len[i] = 0;
}

static void run_lines(control_t *c, int i)
{
    char *start = c->buf[i];
    char *nl;
    while ((nl = memchr(start, '\n', c->len[i] - (size_t)(start - c->buf[i]))) != NULL) {
        *nl = '\0';
        if (nl > start && nl[-1] == '\r')
            nl[-1] = '\0';
        char reply[CONTROL_LINE];
        reply[0] = '\0';
        c->handler(c->ctx, start, reply, sizeof reply - 1);
        size_t n = strlen(reply);
        reply[n++] = '\n';
        if (send(c->fds[i], reply, n, MSG_NOSIGNAL | MSG_DONTWAIT) != (ssize_t)n) {
            drop_client(c, i);
            return;
        }
        start = nl + 1;
    }
    size_t rest = c->len[i] - (size_t)(start - c->buf[i]);
    memmove(c->buf[i], start, rest);
    c->len[i] = rest;
    if (rest == sizeof c->buf[i]) {
        const char msg[] = "error line too long\n";
        send(c->fds[i], msg, sizeof msg - 1, MSG_NOSIGNAL | MSG_DONTWAIT);
        drop_client(c, i);
    }
}

void control_service(control_t *c)
{
    if (c->listen_fd < 0)
        return;
    for (;;) {
        int fd = accept(c->listen_fd, NULL, NULL);
        if (fd < 0)
            break;
        int slot = -1;
        for (int i = 0; i < CONTROL_MAX_CLIENTS; i++)
            if (c->fds[i] < 0) {
                slot = i;
                break;
            }
        if (slot < 0) {
            const char msg[] = "error too many control clients\n";
            send(fd, msg, sizeof msg - 1, MSG_NOSIGNAL | MSG_DONTWAIT);
            close(fd);
            continue;
        }
        fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
        c->fds[slot] = fd;
        c->len[slot] = 0;
    }
    for (int i = 0; i < CONTROL_MAX_CLIENTS; i++) {
        if (c->fds[i] < 0)
            continue;
        ssize_t r = recv(c->fds[i], c->buf[i] + c->len[i], sizeof c->buf[i] - c->len[i], 0);
        if (r == 0 || (r < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) {
            drop_client(c, i);
            continue;
        }
        if (r > 0) {
            c->len[i] += (size_t)r;
            run_lines(c, i);
        }
    }
}

int control_fds(const control_t *c, int *fds, int max)
{
    int n = 0;
    if (c->listen_fd >= 0 && n < max)
        fds[n++] = c->listen_fd;
    for (int i = 0; i < CONTROL_MAX_CLIENTS && n < max; i++)
        if (c->fds[i] >= 0)
            fds[n++] = c->fds[i];
    return n;
}

void control_close(control_t *c)
{
    for (int i = 0; i < CONTROL_MAX_CLIENTS; i++)
        if (c->fds[i] >= 0)
            drop_client(c, i);
    if (c->listen_fd >= 0) {
        close(c->listen_fd);
        unlink(c->path);
        c->listen_fd = -1;
    }
}
