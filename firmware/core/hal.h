/* The board interface the portable core needs: a timer, the sonar pins, the UART rings,
 * idle and watchdog. Each board implements it in boards/<board>/; the native tests
 * implement it with a fake in tests/native/. Nothing here names a register. */
#ifndef OF_HAL_H
#define OF_HAL_H

#include <stdbool.h>
#include <stdint.h>

/* board.h (one per board, found on the include path) defines:
 *   HAL_BOARD          OF_BOARD_* value announced in HELLO
 *   HAL_TIMER_HZ       echo timer clock, a whole number of MHz
 *   HAL_SENSOR_COUNT   how many TRIG pins the board drives (<= OF_MAX_SENSORS) */
#include "board.h"

#define HAL_TICKS_PER_US ((uint32_t)(HAL_TIMER_HZ / 1000000UL))

/* Brings up clocks, timer, pins, UART and watchdog; interrupts are enabled on return. */
void hal_init(void);

/* The CPU clock actually running (a board may fall back to its internal oscillator). */
uint32_t hal_cpu_hz(void);

/* Free-running 32-bit microsecond clock; wraps after 2^32 us (about 71.6 minutes). */
uint32_t hal_micros(void);

/* The echo timer extended to 32 bits, in 1/HAL_TIMER_HZ ticks; same clock as captures. */
uint32_t hal_ticks(void);

/* Arms echo capture for a new measurement, raises TRIG of `sensor` for 10 us (the only
 * busy wait in the firmware) and returns hal_micros() at TRIG's rising edge. */
uint32_t hal_trigger(uint8_t sensor);

/* Echo edges captured since hal_trigger(): 0 none yet, 1 the rise, 2 rise and fall.
 * rise/fall get the captured 32-bit ticks of the edges present (read atomically). */
uint8_t hal_echo_edges(uint32_t *rise_ticks, uint32_t *fall_ticks);

/* Stops capturing edges (measurement finished or aborted). */
void hal_echo_disarm(void);

/* Current level of the ECHO line (for the cross-talk guard). */
bool hal_echo_is_high(void);

/* Next received byte, false if none. For a 0x00 frame delimiter *stamp_us is
 * hal_micros() when that byte arrived (taken in the receive interrupt). */
bool hal_uart_read(uint8_t *byte, uint32_t *stamp_us);

/* Queues all n bytes for transmission or none of them (false: not enough room).
 * Never blocks; transmission is interrupt driven. */
bool hal_uart_write(const uint8_t *data, uint8_t n);

/* Sleeps until an interrupt, or until about wake_us (the board may wake earlier). */
void hal_idle_until(uint32_t wake_us);

/* Whether the last reset was the watchdog's (the main loop hung). */
bool hal_reset_by_watchdog(void);

/* Tells the watchdog the main loop is alive. */
void hal_watchdog_kick(void);

#endif /* OF_HAL_H */
