/* Stand-in for simavr's avr_mcu_section.h when libsimavr-dev is absent: the ELF then
 * carries no part/clock tag and simavr needs -m atmega328p -f 16000000. */
#ifndef OF_NOSIMAVR_MCU_SECTION_H
#define OF_NOSIMAVR_MCU_SECTION_H
#define AVR_MCU(speed, name) extern int of_no_mmcu_tag
#endif
