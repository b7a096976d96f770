/* The Uno's own bootloader under simavr.
 *
 * A real Uno holds Optiboot in the top 512 bytes of its flash with the BOOTRST fuse
 * programmed: every reset starts there, and Optiboot either answers avrdude (STK500v1 on
 * the UART) or jumps to address 0, the application. It stays only after an external
 * reset (EXTRF in MCUSR), which the USB-serial chip causes by pulsing RESET when the port
 * is opened (DTR). A watchdog reset (how Optiboot ends a session) or power-on goes
 * straight to the application. simavr clears the I/O registers on reset and sets WDRF
 * itself after a watchdog reset; the emulator marks the external resets it makes. */
#include "bootloader.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "sim_regbit.h"

#define MCUSR_ADDR_M328 0x54 /* MCUSR: I/O 0x34 + 0x20 on the ATmega48/88/168/328 */
#define BIT_PORF 0
#define BIT_EXTRF 1

static int hexval(const char *s, int digits, uint32_t *out)
{
    uint32_t v = 0;
    for (int i = 0; i < digits; i++) {
        char c = s[i];
        int d = c >= '0' && c <= '9' ? c - '0'
              : c >= 'A' && c <= 'F' ? c - 'A' + 10
              : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
        if (d < 0)
            return -1;
        v = v << 4 | (uint32_t)d;
    }
    *out = v;
    return 0;
}

/* Intel HEX records 00 (data), 01 (end), 02/04 (segment/linear base), 03/05 (start address,
 * informative). simavr 1.6's reader stops at the 03 record Optiboot's hex carries, so the
 * file is read here, straight into the flash. */
int bootloader_load(bootloader_t *b, avr_t *avr, char *err, size_t n)
{
    FILE *f = fopen(b->path, "r");
    if (!f) {
        snprintf(err, n, "bootloader %s: %s", b->path, strerror(errno));
        return -1;
    }
    const uint32_t flash_size = avr->flashend + 1u;
    uint32_t base = 0, lo = UINT32_MAX, total = 0;
    int lineno = 0, ended = 0;
    char line[600];
    while (!ended && fgets(line, sizeof line, f)) {
        lineno++;
        size_t len = strcspn(line, "\r\n");
        line[len] = 0;
        if (len == 0)
            continue;
        uint32_t count, addr, type, sum = 0, v;
        if (line[0] != ':' || len < 11 || hexval(line + 1, 2, &count) ||
            hexval(line + 3, 4, &addr) || hexval(line + 7, 2, &type) ||
            len != 11 + 2 * count) {
            snprintf(err, n, "bootloader %s line %d: not an Intel HEX record", b->path, lineno);
            fclose(f);
            return -1;
        }
        uint8_t data[256];
        for (uint32_t i = 0; i < count + 4 + 1; i++) {
            if (hexval(line + 1 + 2 * i, 2, &v)) {
                snprintf(err, n, "bootloader %s line %d: bad hex digit", b->path, lineno);
                fclose(f);
                return -1;
            }
            sum += v;
            if (i >= 4 && i < count + 4)
                data[i - 4] = (uint8_t)v;
        }
        if ((sum & 0xFF) != 0) {
            snprintf(err, n, "bootloader %s line %d: checksum error", b->path, lineno);
            fclose(f);
            return -1;
        }
        switch (type) {
        case 0: {
            uint32_t at = base + addr;
            if (at + count > flash_size || at < flash_size / 2u) {
                snprintf(err, n,
                         "bootloader %s line %d: bytes at 0x%05x..0x%05x are outside the boot "
                         "section (upper half of the %u-byte flash of the %s)",
                         b->path, lineno, (unsigned)at, (unsigned)(at + count),
                         (unsigned)flash_size, avr->mmcu);
                fclose(f);
                return -1;
            }
            memcpy(avr->flash + at, data, count);
            if (at < lo)
                lo = at;
            total += count;
            break;
        }
        case 1: ended = 1; break;
        case 2: base = (uint32_t)(data[0] << 8 | data[1]) << 4; break;
        case 4: base = (uint32_t)(data[0] << 8 | data[1]) << 16; break;
        case 3: case 5: break;
        default:
            snprintf(err, n, "bootloader %s line %d: unknown record type %02x", b->path, lineno,
                     (unsigned)type);
            fclose(f);
            return -1;
        }
    }
    fclose(f);
    if (total == 0) {
        snprintf(err, n, "bootloader %s: no data records", b->path);
        return -1;
    }
    /* BOOTRST: the reset vector is the boot section's start, Optiboot's lowest address. */
    b->start = lo;
    b->size = total;
    b->active = 1;
    avr->reset_pc = lo;
    avr->pc = lo;
    if (avr->codeend < avr->flashend)
        avr->codeend = avr->flashend;
    return 0;
}

void bootloader_mark_reset(avr_t *avr, int external)
{
    int bit = external ? BIT_EXTRF : BIT_PORF;
    avr_regbit_t rb = external ? avr->reset_flags.extrf : avr->reset_flags.porf;
    if (rb.reg) {
        avr_regbit_set(avr, rb);
        return;
    }
    avr->data[MCUSR_ADDR_M328] |= (uint8_t)(1u << bit);
}
