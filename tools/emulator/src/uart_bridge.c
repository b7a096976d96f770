/* The host sees bytes when they would have left the wire: a byte written to UDR0 at cycle
 * c reaches the pty once simulated time passes c + one byte time. Host bytes reach the
 * USART no faster than one per byte time and never into a full simavr RX FIFO. */
#include "uart_bridge.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "sim_cycle_timers.h"
#include "sim_io.h"

int bridge_open_pty(uart_bridge_t *b)
{
    int m = posix_openpt(O_RDWR | O_NOCTTY);
    if (m < 0)
        return -1;
    if (grantpt(m) || unlockpt(m)) {
        close(m);
        return -1;
    }
    const char *name = ptsname(m);
    if (!name) {
        close(m);
        return -1;
    }
    snprintf(b->path, sizeof b->path, "%s", name);
    /* Raw mode on the slave, so nothing is echoed or translated before a client
     * configures the port itself. */
    int s = open(b->path, O_RDWR | O_NOCTTY);
    if (s >= 0) {
        struct termios t;
        if (tcgetattr(s, &t) == 0) {
            cfmakeraw(&t);
            cfsetispeed(&t, B115200);
            cfsetospeed(&t, B115200);
            tcsetattr(s, TCSANOW, &t);
        }
        close(s);
    }
    int fl = fcntl(m, F_GETFL);
    fcntl(m, F_SETFL, fl | O_NONBLOCK);
    b->master = m;
    b->client = 0;
    return 0;
}

avr_cycle_count_t bridge_cycles_per_byte(const uart_bridge_t *b)
{
    avr_cycle_count_t c = b->uart ? b->uart->cycles_per_byte : 0;
    return c ? c : 1;
}

static int apply_faults(uart_bridge_t *b, int dir, uint8_t in, uint8_t out[2])
{
    const uart_faults_t *f = &b->faults;
    if (!(f->dirs & dir))
        return out[0] = in, 1;
    if (rng_chance(b->rng, f->drop_p)) {
        b->st.dropped++;
        return 0;
    }
    int n = 0;
    if (rng_chance(b->rng, f->corrupt_p)) {
        in ^= (uint8_t)(1u << (rng_next(b->rng) % 8));
        b->st.corrupted++;
    }
    out[n++] = in;
    if (rng_chance(b->rng, f->insert_p)) {
        out[n++] = (uint8_t)rng_next(b->rng);
        b->st.inserted++;
    }
    return n;
}

static void tx_push(uart_bridge_t *b, uint8_t v, avr_cycle_count_t due)
{
    if (b->tx_head - b->tx_tail >= BRIDGE_TX_SIZE) {
        b->st.tx_overflow++;
        return;
    }
    uint32_t i = b->tx_head++ & (BRIDGE_TX_SIZE - 1);
    b->tx_buf[i] = v;
    b->tx_due[i] = due;
}

static void on_tx(avr_irq_t *irq, uint32_t value, void *param)
{
    uart_bridge_t *b = param;
    (void)irq;
    b->st.tx_bytes++;
    avr_cycle_count_t due = b->avr->cycle + bridge_cycles_per_byte(b);
    uint8_t out[2];
    int n = apply_faults(b, FAULT_TX, (uint8_t)value, out);
    for (int i = 0; i < n; i++)
        tx_push(b, out[i], due);
}

/* simavr's RX FIFO fill level (its accessors are only defined inside the library). */
static unsigned fifo_used(const uart_fifo_t *f)
{
    return (unsigned)((f->write + uart_fifo_fifo_size) - f->read) & (uart_fifo_fifo_size - 1);
}

static avr_cycle_count_t rx_feed(avr_t *avr, avr_cycle_count_t when, void *param)
{
    uart_bridge_t *b = param;
    (void)avr;
    avr_cycle_count_t cpb = bridge_cycles_per_byte(b);
    if (b->rx_head == b->rx_tail) {
        b->rx_scheduled = 0;
        return 0;
    }
    uart_fifo_t *fifo = &b->uart->input;
    if (fifo_used(fifo) >= uart_fifo_fifo_size - 1)
        return when + cpb;   /* simavr would drop it: wait a byte time */
    uint8_t v = b->rx_buf[b->rx_tail++ & (BRIDGE_RX_SIZE - 1)];
    /* The chip holds two received bytes plus one in the shift register; simavr holds
     * 64. A byte that would overrun the chip is lost here as it would be there. */
    if (b->model_rx_overrun && fifo_used(fifo) >= 3) {
        b->st.rx_overruns++;
    } else {
        uint8_t out[2];
        int n = apply_faults(b, FAULT_RX, v, out);
        if (n > 0) {
            avr_raise_irq(b->in_irq, out[0]);
            b->st.rx_fed++;
        }
        if (n > 1) {
            /* An inserted byte takes the next byte slot, ahead of the queue. */
            b->rx_buf[--b->rx_tail & (BRIDGE_RX_SIZE - 1)] = out[1];
        }
    }
    return when + cpb;
}

int bridge_attach(uart_bridge_t *b, avr_t *avr, rng_t *rng, const uart_faults_t *f,
                  int model_rx_overrun)
{
    b->avr = avr;
    b->rng = rng;
    b->faults = *f;
    b->model_rx_overrun = model_rx_overrun;
    b->uart = NULL;
    for (avr_io_t *io = avr->io_port; io; io = io->next) {
        if (io->irq_ioctl_get == AVR_IOCTL_UART_GETIRQ('0'))
            b->uart = (avr_uart_t *)io;
    }
    if (!b->uart)
        return -1;
    /* No console echo of UART bytes, no usleep() when the firmware polls UCSR0A. */
    uint32_t flags = 0;
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    b->in_irq = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
    avr_irq_t *out = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT);
    if (!b->in_irq || !out)
        return -1;
    avr_irq_register_notify(out, on_tx, b);
    b->tx_head = b->tx_tail = 0;
    b->rx_head = b->rx_tail = 0;
    b->rx_scheduled = 0;
    return 0;
}

void bridge_flush(uart_bridge_t *b)
{
    b->tx_tail = b->tx_head;
    b->rx_tail = b->rx_head;
    avr_cycle_timer_cancel(b->avr, rx_feed, b);
    b->rx_scheduled = 0;
}

int bridge_client_present(uart_bridge_t *b)
{
    struct pollfd p = {b->master, POLLIN, 0};
    if (poll(&p, 1, 0) < 0)
        return b->client;
    return !(p.revents & POLLHUP);
}

static void tx_flush(uart_bridge_t *b)
{
    avr_cycle_count_t now = b->avr->cycle;
    uint8_t chunk[4096];
    while (b->tx_tail != b->tx_head) {
        size_t n = 0;
        uint32_t t = b->tx_tail;
        while (t != b->tx_head && n < sizeof chunk) {
            uint32_t i = t & (BRIDGE_TX_SIZE - 1);
            if (b->tx_due[i] > now)
                break;
            chunk[n++] = b->tx_buf[i];
            t++;
        }
        if (n == 0)
            return;
        if (!b->client) {
            b->st.tx_no_client += n;
            b->tx_tail += (uint32_t)n;
            continue;
        }
        ssize_t w = write(b->master, chunk, n);
        if (w <= 0)
            return;   /* EAGAIN: the host is not reading; keep the bytes */
        b->st.tx_written += (uint64_t)w;
        b->tx_tail += (uint32_t)w;
        if ((size_t)w < n)
            return;
    }
}

static void rx_read(uart_bridge_t *b)
{
    uint8_t chunk[1024];
    for (;;) {
        uint32_t space = BRIDGE_RX_SIZE - (b->rx_head - b->rx_tail);
        /* Full: the rest waits in the pty (the host's write blocks, as on a real line),
         * but the feed below must still be scheduled, or nothing ever empties the queue. */
        if (space == 0)
            break;
        size_t want = space < sizeof chunk ? space : sizeof chunk;
        ssize_t r = read(b->master, chunk, want);
        if (r <= 0)
            break;
        b->st.rx_bytes += (uint64_t)r;
        for (ssize_t i = 0; i < r; i++)
            b->rx_buf[b->rx_head++ & (BRIDGE_RX_SIZE - 1)] = chunk[i];
        if ((size_t)r < want)
            break;
    }
    if (b->rx_head != b->rx_tail && !b->rx_scheduled) {
        b->rx_scheduled = 1;
        avr_cycle_timer_register(b->avr, bridge_cycles_per_byte(b), rx_feed, b);
    }
}

int bridge_service(uart_bridge_t *b)
{
    return bridge_service_ex(b, 1);
}

int bridge_service_ex(uart_bridge_t *b, int deliver_tx)
{
    struct pollfd p = {b->master, POLLIN, 0};
    int opened = 0;
    if (poll(&p, 1, 0) >= 0) {
        int present = !(p.revents & POLLHUP);
        if (present && !b->client) {
            opened = 1;
            b->st.client_opens++;
        }
        b->client = present;
    }
    if (deliver_tx)
        tx_flush(b);
    if (b->client && (p.revents & POLLIN))
        rx_read(b);
    return opened;
}

void bridge_drain(uart_bridge_t *b, double timeout_s)
{
    struct timespec t0, now;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    /* Everything still queued goes out now, then we wait for the client to read it:
     * unread input is lost when the master closes. The slave's input queue is shared by
     * all its descriptors, so our own descriptor can measure it. */
    bridge_service(b);
    if (!b->client) {
        b->st.tx_no_client += b->tx_head - b->tx_tail;
        b->tx_tail = b->tx_head;
        return;
    }
    int s = open(b->path, O_RDWR | O_NOCTTY | O_NONBLOCK);
    int quiet = 0;
    for (;;) {
        b->avr->cycle += bridge_cycles_per_byte(b) * 64;
        bridge_service(b);
        int pending = 0;
        if (s >= 0 && ioctl(s, FIONREAD, &pending) != 0)
            pending = 0;
        /* Written bytes reach the slave's queue a moment later (the kernel's flip
         * buffer): only several empty looks in a row mean the client has them all. */
        quiet = (b->tx_tail == b->tx_head && pending == 0) ? quiet + 1 : 0;
        if (quiet >= 5)
            break;
        clock_gettime(CLOCK_MONOTONIC, &now);
        double dt = (double)(now.tv_sec - t0.tv_sec) + (double)(now.tv_nsec - t0.tv_nsec) * 1e-9;
        if (dt > timeout_s)
            break;
        usleep(5000);
    }
    if (s >= 0)
        close(s);
}
