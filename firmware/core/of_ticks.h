/* Pure arithmetic that turns a 16-bit hardware timer plus a software overflow count into
 * 32-bit ticks and microseconds. Kept in the core, free of registers, so the one subtle
 * case (an overflow pending while a capture is read) is unit-tested on the host. */
#ifndef OF_TICKS_H
#define OF_TICKS_H

#include <stdbool.h>
#include <stdint.h>

/* The overflow count a 16-bit value belongs to.
 * ovf: overflows already counted by the overflow interrupt;
 * value: a capture register (or the counter) read with interrupts off;
 * ovf_pending: the timer's overflow flag, read after `value`, still set because its
 * interrupt has not run. A pending overflow belongs before `value` only if `value` is in
 * the lower half (the counter has wrapped since); a value in the upper half was taken
 * just before the wrap. Valid while interrupt latency stays under half a timer period. */
static inline uint32_t of_ticks_epoch(uint32_t ovf, uint16_t value, bool ovf_pending)
{
    return (ovf_pending && value < 0x8000u) ? ovf + 1u : ovf;
}

/* 32-bit ticks (wrap at 2^32 ticks); differences of two stamps are exact modulo 2^32. */
static inline uint32_t of_ticks_extend(uint32_t ovf, uint16_t value, bool ovf_pending)
{
    return (of_ticks_epoch(ovf, value, ovf_pending) << 16) | value;
}

/* Microseconds from the same reading, for a timer running 2^us_shift ticks per
 * microsecond; wraps at exactly 2^32 us because the epoch's high bits shift out. */
static inline uint32_t of_ticks_micros(uint32_t ovf, uint16_t value, bool ovf_pending,
                                       uint8_t us_shift)
{
    return (of_ticks_epoch(ovf, value, ovf_pending) << (16u - us_shift))
        | ((uint32_t)value >> us_shift);
}

/* Whether time a is at or after time b on a wrapping 32-bit clock (within 2^31). */
static inline bool of_time_reached(uint32_t a, uint32_t b)
{
    return (int32_t)(a - b) >= 0;
}

#endif /* OF_TICKS_H */
