/* Boot the board's own bootloader (Optiboot on an Uno) instead of, or before, the firmware. */
#ifndef OF_BOOTLOADER_H
#define OF_BOOTLOADER_H

#include <stddef.h>
#include <stdint.h>

#include "sim_avr.h"

typedef struct {
    const char *path;  /* Intel HEX file, e.g. optiboot_atmega328.hex */
    uint32_t start;    /* its lowest byte address: where BOOTRST sends the reset vector */
    uint32_t size;     /* bytes loaded */
    int active;
} bootloader_t;

/* Load the hex into the flash (the part above the application section) and set the
 * reset vector there, as the BOOTRST fuse does. 0, or -1 with a message in err. */
int bootloader_load(bootloader_t *b, avr_t *avr, char *err, size_t n);

/* Set MCUSR as the reset cause leaves it: external (the RESET pin, i.e. DTR through the
 * Uno's capacitor) or power-on. Optiboot stays only after an external reset. */
void bootloader_mark_reset(avr_t *avr, int external);

#endif
