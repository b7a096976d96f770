/* The firmware's entry point, the same on every board: bring the board up, announce,
 * then poll and sleep. */
#include "hal.h"
#include "of_app.h"

static of_app_t app;

int main(void)
{
    hal_init();
    of_app_init(&app);
    for (;;) {
        hal_watchdog_kick();
        hal_idle_until(of_app_poll(&app));
    }
}
