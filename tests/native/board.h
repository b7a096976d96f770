/* The fake board for native tests: Uno-like timing (2 MHz ticks) with four sensors. */
#ifndef OF_BOARD_H
#define OF_BOARD_H

#include "of_protocol.h"

#define HAL_BOARD OF_BOARD_UNO
#define HAL_TIMER_HZ 2000000UL
#define HAL_SENSOR_COUNT 4u

#endif /* OF_BOARD_H */
