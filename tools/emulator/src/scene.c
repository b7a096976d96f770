/* Keyframe parsing and interpolation. The file format is shared with the host (brief):
 * `<time_s> <distance_m|none>` per line, `#` comments, optional `temperature <C>`. */
#include "scene.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

void scene_init(scene_t *s, double distance_m, int none, double temperature_c)
{
    s->kf = NULL;
    s->n = 0;
    s->t0 = 0.0;
    s->constant = distance_m;
    s->constant_none = none;
    s->temperature_c = temperature_c;
}

double sound_speed(double temperature_c)
{
    return 331.3 * sqrt(1.0 + temperature_c / 273.15);
}

static int parse_double(const char *tok, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(tok, &end);
    if (errno || end == tok || *end != '\0' || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

int scene_load(scene_t *s, const char *path, double t0, char *err, size_t errlen)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        snprintf(err, errlen, "cannot open scene file %s: %s", path, strerror(errno));
        return -1;
    }
    char line[512];
    keyframe_t *kf = NULL;
    size_t n = 0, cap = 0;
    int lineno = 0;
    int have_temp = 0;
    double temp = s->temperature_c;
    int rc = 0;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        char *hash = strchr(line, '#');
        if (hash)
            *hash = '\0';
        char *tok[3];
        int ntok = 0;
        for (char *p = strtok(line, " \t\r\n"); p; p = strtok(NULL, " \t\r\n")) {
            if (ntok == 3) {
                ntok++;
                break;
            }
            tok[ntok++] = p;
        }
        if (ntok == 0)
            continue;
        if (ntok != 2) {
            snprintf(err, errlen, "%s:%d: expected `<time_s> <distance_m|none>` or "
                     "`temperature <celsius>`", path, lineno);
            rc = -1;
            break;
        }
        if (strcasecmp(tok[0], "temperature") == 0) {
            if (parse_double(tok[1], &temp) || temp < -100.0 || temp > 100.0) {
                snprintf(err, errlen, "%s:%d: bad temperature '%s' (celsius, -100..100)",
                         path, lineno, tok[1]);
                rc = -1;
                break;
            }
            have_temp = 1;
            continue;
        }
        keyframe_t k = {0.0, 0.0, 0};
        if (parse_double(tok[0], &k.t) || k.t < 0.0) {
            snprintf(err, errlen, "%s:%d: bad time '%s' (seconds, >= 0)", path, lineno, tok[0]);
            rc = -1;
            break;
        }
        if (strcasecmp(tok[1], "none") == 0) {
            k.none = 1;
        } else if (parse_double(tok[1], &k.d) || k.d < 0.0) {
            snprintf(err, errlen, "%s:%d: bad distance '%s' (metres >= 0, or none)",
                     path, lineno, tok[1]);
            rc = -1;
            break;
        }
        if (n > 0 && k.t < kf[n - 1].t) {
            snprintf(err, errlen, "%s:%d: time %g goes backwards (previous keyframe %g)",
                     path, lineno, k.t, kf[n - 1].t);
            rc = -1;
            break;
        }
        if (n == cap) {
            size_t ncap = cap ? cap * 2 : 256;
            keyframe_t *grown = realloc(kf, ncap * sizeof *kf);
            if (!grown) {
                snprintf(err, errlen, "%s:%d: out of memory", path, lineno);
                rc = -1;
                break;
            }
            kf = grown;
            cap = ncap;
        }
        kf[n++] = k;
    }
    if (rc == 0 && ferror(f)) {
        /* A folder opens but cannot be read (EISDIR): say why, as for a missing file. */
        snprintf(err, errlen, "cannot read scene file %s: %s", path, strerror(errno));
        rc = -1;
    }
    fclose(f);
    if (rc == 0 && n == 0 && !have_temp) {
        snprintf(err, errlen, "%s: no keyframes (expected lines `<time_s> <distance_m|none>`)",
                 path);
        rc = -1;
    }
    if (rc) {
        free(kf);
        return rc;
    }
    if (n > 0) {
        free(s->kf);
        s->kf = kf;
        s->n = n;
        s->t0 = t0;
    }
    s->temperature_c = temp;
    return 0;
}

int scene_distance(const scene_t *s, double t, double *d)
{
    if (s->n == 0) {
        if (s->constant_none)
            return -1;
        *d = s->constant;
        return 0;
    }
    double ts = t - s->t0;
    const keyframe_t *k = s->kf;
    size_t n = s->n;
    const keyframe_t *pick;
    if (ts < k[0].t) {
        pick = &k[0];
    } else if (ts >= k[n - 1].t) {
        pick = &k[n - 1];
    } else {
        /* Last keyframe with t <= ts; equal times make a step to the later one. */
        size_t lo = 0, hi = n - 1;
        while (hi - lo > 1) {
            size_t mid = (lo + hi) / 2;
            if (k[mid].t <= ts)
                lo = mid;
            else
                hi = mid;
        }
        const keyframe_t *a = &k[lo], *b = &k[hi];
        if (a->none || b->none || b->t <= a->t) {
            pick = a;
        } else {
            double f = (ts - a->t) / (b->t - a->t);
            *d = a->d + f * (b->d - a->d);
            return 0;
        }
    }
    if (pick->none)
        return -1;
    *d = pick->d;
    return 0;
}
