/* ms_marks — what happened to the intercept, from its `intercept` messages:
 * designations, phases, re-plans, hand-overs to another track, cancels. The
 * replay's timeline and the report mark them. Pure. */
#ifndef MS_MARKS_H
#define MS_MARKS_H

#include "intercept.pb-c.h"

#include <stddef.h>
#include <stdint.h>

#define MS_MARKS_UAVS 8 // UAVs followed

typedef struct {
    double t_s;      // when (the caller's time base)
    char kind[16];   // "designate", "phase", "replan", "handover", "cancel"
    char text[96];   // for a person
    uint32_t uav_id; // whose intercept
} ms_mark_t;

typedef struct {
    ms_mark_t *marks;
    size_t n, cap;
    struct {
        uint32_t uav_id;
        uint64_t designation;
        uint32_t track_id, replans;
        int state;
        int seen;
    } last[MS_MARKS_UAVS];
} ms_marks_t;

/* Take one intercept message at time t_s: the marks it makes are appended.
 * 0, or -ENOMEM. */
int ms_marks_add (ms_marks_t *self, const Cgs__Intercept *m, double t_s);
/* Free the marks; the object may be used again. */
void ms_marks_clear (ms_marks_t *self);

#endif
