/* Tags the ELF with the part and clock (a .mmcu section that never reaches the chip), so
 * simavr needs no command-line flags. Built without LTO: nothing references these
 * constants, and LTO would drop them. */
#include "avr_mcu_section.h"

AVR_MCU(F_CPU, "atmega328p");
