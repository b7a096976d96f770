/* The world in front of the sensor: obstacle distance over time and air temperature. */
#ifndef OF_EMU_SCENE_H
#define OF_EMU_SCENE_H

#include <stddef.h>

typedef struct {
    double t;      /* seconds, scene time */
    double d;      /* metres; ignored when none */
    int none;      /* no obstacle */
} keyframe_t;

typedef struct {
    keyframe_t *kf;    /* heap array of n keyframes (no limit on a scene's length) */
    size_t n;          /* 0: constant distance below */
    double t0;         /* simulated true time at which scene time 0 starts */
    double constant;   /* used when n == 0 */
    int constant_none;
    double temperature_c;
} scene_t;

void scene_init(scene_t *s, double distance_m, int none, double temperature_c);
/* Parse a keyframe file (format in tools/emulator/README.md) into s, replacing its
 * keyframes; t0 is the true time that scene time 0 maps to. On error returns -1 and
 * writes a message naming the file and line to err; s is then unchanged. */
int scene_load(scene_t *s, const char *path, double t0, char *err, size_t errlen);
/* Distance at true time t; returns 0 with *d set, or -1 when there is no obstacle. */
int scene_distance(const scene_t *s, double t, double *d);
/* Speed of sound in air at temperature_c, m/s. */
double sound_speed(double temperature_c);

#endif
