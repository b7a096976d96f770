/* Command handling, protocol output, heartbeat; see of_app.h. */
#include "of_app.h"

#include "hal.h"
#include "of_ticks.h"

/* How close a due trigger must be for a heartbeat to wait until after it. */
#define OF_HEARTBEAT_DEFER_US 1000UL

/* Encodes one message and queues it whole; a frame that does not fit is dropped and
 * counted, never sent in part and never waited for. */
static void send(of_app_t *app, uint8_t msg_id, const uint8_t *payload, uint8_t len)
{
    uint8_t frame[OF_MAX_FRAME];
    size_t n = of_frame_encode(frame, sizeof frame, msg_id, app->tx_seq++, payload, len);
    if (n > 0u && hal_uart_write(frame, (uint8_t)n)) {
        app->frames_sent++;
    } else {
        app->tx_overruns++;
    }
}

static void send_hello(of_app_t *app)
{
    of_hello_t m;
    uint8_t p[OF_MSG_HELLO_LEN];
    m.protocol_version = OF_PROTOCOL_VERSION;
    m.schema_fingerprint = OF_SCHEMA_FINGERPRINT;
    m.fw_major = OF_FW_MAJOR;
    m.fw_minor = OF_FW_MINOR;
    m.fw_patch = OF_FW_PATCH;
    m.board = HAL_BOARD;
    m.cpu_hz = hal_cpu_hz();
    m.timer_hz = HAL_TIMER_HZ;
    m.sensor_count = HAL_SENSOR_COUNT;
    send(app, OF_MSG_HELLO, p, of_hello_pack(&m, p));
}

static void send_config(of_app_t *app)
{
    of_config_t m;
    uint8_t p[OF_MSG_CONFIG_LEN];
    m.cycle_ms = app->cfg.cycle_ms;
    m.sensor_mask = app->cfg.sensor_mask;
    m.max_echo_us = app->cfg.max_echo_us;
    m.echo_timeout_us = app->cfg.echo_timeout_us;
    m.heartbeat_ms = app->cfg.heartbeat_ms;
    m.state = app->ranger.running ? OF_RUN_STATE_RUNNING : OF_RUN_STATE_STOPPED;
    send(app, OF_MSG_CONFIG, p, of_config_pack(&m, p));
}

static void send_ack(of_app_t *app, const of_frame_t *f)
{
    of_ack_t m;
    uint8_t p[OF_MSG_ACK_LEN];
    m.command_id = f->msg_id;
    m.command_seq = f->seq;
    send(app, OF_MSG_ACK, p, of_ack_pack(&m, p));
}

static void send_nack(of_app_t *app, const of_frame_t *f, uint8_t error)
{
    of_nack_t m;
    uint8_t p[OF_MSG_NACK_LEN];
    m.command_id = f->msg_id;
    m.command_seq = f->seq;
    m.error = error;
    send(app, OF_MSG_NACK, p, of_nack_pack(&m, p));
}

static void send_heartbeat(of_app_t *app)
{
    of_heartbeat_t m;
    uint8_t p[OF_MSG_HEARTBEAT_LEN];
    m.uptime_ms = app->uptime_ms;
    m.frames_sent = app->frames_sent;
    m.rx_errors = app->rx_errors;
    m.tx_overruns = app->tx_overruns;
    m.state = app->ranger.running ? OF_RUN_STATE_RUNNING : OF_RUN_STATE_STOPPED;
    send(app, OF_MSG_HEARTBEAT, p, of_heartbeat_pack(&m, p));
}

static void send_log(of_app_t *app, uint8_t level, const char *text)
{
    of_log_t m;
    uint8_t p[OF_MSG_LOG_MAX_LEN];
    m.level = level;
    m.text_len = 0;
    /* The bound first: a 40-character text without a terminator is never read past. */
    while (m.text_len < sizeof m.text && text[m.text_len] != '\0') {
        m.text[m.text_len] = text[m.text_len];
        m.text_len++;
    }
    send(app, OF_MSG_LOG, p, of_log_pack(&m, p));
}

static void ranger_config(const of_set_config_t *c, of_ranger_config_t *rc)
{
    rc->cycle_us = (uint32_t)c->cycle_ms * 1000u;
    rc->max_echo_us = c->max_echo_us;
    rc->echo_timeout_us = c->echo_timeout_us;
    rc->sensor_mask = c->sensor_mask;
}

uint8_t of_app_validate(const of_set_config_t *c, uint8_t sensor_count)
{
    if (c->echo_timeout_us < OF_MIN_ECHO_TIMEOUT_US
        || c->echo_timeout_us > OF_MAX_ECHO_TIMEOUT_US) {
        return OF_ERROR_BAD_TIMEOUT;
    }
    if (c->cycle_ms < OF_MIN_CYCLE_MS || c->cycle_ms > OF_MAX_CYCLE_MS
        || (uint32_t)c->cycle_ms * 1000u <= c->echo_timeout_us) {
        return OF_ERROR_BAD_CYCLE;
    }
    if (c->max_echo_us < 1u || c->max_echo_us > c->echo_timeout_us) {
        return OF_ERROR_BAD_MAX_ECHO;
    }
    uint8_t allowed = (uint8_t)((1u << sensor_count) - 1u);
    if (c->sensor_mask == 0u || (c->sensor_mask & (uint8_t)~allowed) != 0u) {
        return OF_ERROR_BAD_SENSOR_MASK;
    }
    if (c->heartbeat_ms != 0u && c->heartbeat_ms < 100u) {
        return OF_ERROR_BAD_HEARTBEAT;
    }
    return OF_ERROR_NONE;
}

static void handle_set_config(of_app_t *app, const of_frame_t *f)
{
    of_set_config_t c;
    if (!of_set_config_unpack(&c, f->payload, f->len)) {
        send_nack(app, f, OF_ERROR_BAD_LENGTH);
        return;
    }
    uint8_t err = of_app_validate(&c, HAL_SENSOR_COUNT);
    if (err != OF_ERROR_NONE) {
        send_nack(app, f, err);
        return;
    }
    uint32_t now = hal_micros();
    app->cfg = c;
    /* The new period counts from now: the next trigger as soon as the guard allows (a
     * measurement in flight ends first, under the new limits, which are valid alone). */
    app->ranger.next_due_us = now;
    app->next_heartbeat_us = now + (uint32_t)c.heartbeat_ms * 1000u;
    send_ack(app, f);
    send_config(app);
}

static void handle_time_sync(of_app_t *app, const of_frame_t *f, uint32_t rx_us)
{
    of_time_sync_t req;
    if (!of_time_sync_unpack(&req, f->payload, f->len)) {
        send_nack(app, f, OF_ERROR_BAD_LENGTH);
        return;
    }
    of_time_sync_reply_t m;
    uint8_t p[OF_MSG_TIME_SYNC_REPLY_LEN];
    m.token = req.token;
    m.rx_us = rx_us;
    m.tx_us = hal_micros(); /* last moment before the reply is encoded and queued */
    send(app, OF_MSG_TIME_SYNC_REPLY, p, of_time_sync_reply_pack(&m, p));
}

void of_app_handle_frame(of_app_t *app, const of_frame_t *f, uint32_t rx_us)
{
    switch (f->msg_id) {
    case OF_MSG_GET_INFO:
    case OF_MSG_START:
    case OF_MSG_STOP:
        if (f->len != 0u) {
            send_nack(app, f, OF_ERROR_BAD_LENGTH);
        } else if (f->msg_id == OF_MSG_GET_INFO) {
            send_hello(app);
            send_config(app);
        } else if (f->msg_id == OF_MSG_START) {
            of_ranger_start(&app->ranger, hal_micros());
            send_ack(app, f);
        } else {
            of_ranger_stop(&app->ranger);
            send_ack(app, f);
        }
        break;
    case OF_MSG_SET_CONFIG:
        handle_set_config(app, f);
        break;
    case OF_MSG_TIME_SYNC:
        handle_time_sync(app, f, rx_us);
        break;
    default:
        send_nack(app, f, OF_ERROR_UNKNOWN_COMMAND);
        break;
    }
}

void of_app_init(of_app_t *app)
{
    app->cfg.cycle_ms = OF_DEFAULT_CYCLE_MS;
    app->cfg.sensor_mask = 1u;
    app->cfg.max_echo_us = OF_DEFAULT_MAX_ECHO_US;
    app->cfg.echo_timeout_us = OF_DEFAULT_ECHO_TIMEOUT_US;
    app->cfg.heartbeat_ms = OF_DEFAULT_HEARTBEAT_MS;
    of_ranger_init(&app->ranger);
    of_frame_decoder_init(&app->decoder);
    app->tx_seq = 0;
    app->frames_sent = 0;
    app->rx_errors = 0;
    app->tx_overruns = 0;
    app->uptime_ms = 0;
    uint32_t now = hal_micros();
    app->uptime_mark_us = now;
    app->next_heartbeat_us = now + OF_DEFAULT_HEARTBEAT_MS * 1000u;
    of_ranger_start(&app->ranger, now);
    send_hello(app);
    send_config(app);
    if (hal_reset_by_watchdog()) {
        /* The host learns the firmware hung, not just that it restarted. */
        send_log(app, OF_LOG_LEVEL_WARNING, "watchdog reset");
    }
}

static void poll_rx(of_app_t *app)
{
    uint8_t byte;
    uint32_t stamp = 0;
    of_frame_t frame;
    for (uint8_t i = 0; i < OF_RX_BYTES_PER_POLL && hal_uart_read(&byte, &stamp); i++) {
        of_feed_result_t res = of_frame_decoder_feed(&app->decoder, byte, &frame);
        if (res == OF_FEED_FRAME) {
            of_app_handle_frame(app, &frame, stamp);
        } else if (res == OF_FEED_ERROR) {
            app->rx_errors++;
        }
    }
}

/* The earlier of two times on the wrapping clock (both within 2^31 us of now). */
static uint32_t earlier(uint32_t a, uint32_t b)
{
    return (int32_t)(a - b) < 0 ? a : b;
}

uint32_t of_app_poll(of_app_t *app)
{
    poll_rx(app);

    of_ranger_config_t rc;
    of_range_t range;
    uint32_t wake;
    ranger_config(&app->cfg, &rc);
    if (of_ranger_poll(&app->ranger, &rc, &range, &wake)) {
        uint8_t p[OF_MSG_RANGE_LEN];
        send(app, OF_MSG_RANGE, p, of_range_pack(&range, p));
    }

    uint32_t now = hal_micros();
    /* Whole milliseconds since the mark; the loop runs about once per call since the
     * board polls every few ms, and spares the AVR a 32-bit division. */
    while (now - app->uptime_mark_us >= 1000u) {
        app->uptime_ms++;
        app->uptime_mark_us += 1000u;
    }
    /* Encoding a HEARTBEAT takes a few hundred microseconds on an AVR; when a trigger is
     * about due, the heartbeat waits for it so that triggers keep their period. */
    bool trigger_soon = app->ranger.running && app->ranger.state == OF_RANGER_IDLE
        && (int32_t)(app->ranger.next_due_us - now) < (int32_t)OF_HEARTBEAT_DEFER_US;
    if (app->cfg.heartbeat_ms != 0u) {
        if (!trigger_soon && of_time_reached(now, app->next_heartbeat_us)) {
            uint32_t period = (uint32_t)app->cfg.heartbeat_ms * 1000u;
            send_heartbeat(app);
            app->next_heartbeat_us += period;
            if (of_time_reached(now, app->next_heartbeat_us)) {
                app->next_heartbeat_us = now + period;
            }
        }
        if (!trigger_soon) {
            wake = earlier(wake, app->next_heartbeat_us);
        }
    }
    return wake;
}
