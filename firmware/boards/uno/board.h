/* Arduino Uno (ATmega328P, 16 MHz): what the portable core needs to know. */
#ifndef OF_BOARD_H
#define OF_BOARD_H

#include "of_protocol.h"

#define HAL_BOARD OF_BOARD_UNO
#define HAL_TIMER_HZ 2000000UL /* Timer1, 16 MHz / 8 */
#define HAL_SENSOR_COUNT 4u     /* TRIG on D9..D12 (PB1..PB4); ECHOs OR-ed onto D8 */

#endif /* OF_BOARD_H */
