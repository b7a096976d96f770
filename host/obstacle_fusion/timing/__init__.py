"""Time on one clock: ``clock`` maps the MCU's microsecond clock onto the host's monotonic
clock (offset and skew from TIME_SYNC round trips and one-way RANGE timing).
"""
