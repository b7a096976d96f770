/* Seeded random numbers, so a fault or noise run can be replayed exactly. */
#ifndef OF_EMU_RNG_H
#define OF_EMU_RNG_H

#include <stdint.h>

typedef struct {
    uint64_t s;
    int have_spare;
    double spare;
} rng_t;

void rng_seed(rng_t *r, uint64_t seed);
uint64_t rng_next(rng_t *r);
/* Uniform in [0, 1). */
double rng_uniform(rng_t *r);
/* True with probability p. */
int rng_chance(rng_t *r, double p);
/* Standard normal deviate. */
double rng_gauss(rng_t *r);

#endif
