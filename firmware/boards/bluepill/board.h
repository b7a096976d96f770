/* Blue pill (STM32F103C8, 72 MHz from the 8 MHz crystal): what the portable core needs. */
#ifndef OF_BOARD_H
#define OF_BOARD_H

#include "of_protocol.h"

#define HAL_BOARD OF_BOARD_BLUEPILL
#define HAL_TIMER_HZ 8000000UL /* TIM2 prescaled to 8 MHz whatever the system clock */
#define HAL_SENSOR_COUNT 4u     /* TRIG on PB12..PB15; ECHOs OR-ed onto PA0 */

#endif /* OF_BOARD_H */
