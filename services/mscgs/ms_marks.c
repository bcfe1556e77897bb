/* ms_marks — the intercept's changes as marks on a time line. */
#include "ms_marks.h"

#include "cgs_msg.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int s_mark (ms_marks_t *self, double t_s, uint32_t uav, const char *kind, const char *fmt,
                   ...) __attribute__ ((format (printf, 5, 6)));
static int s_mark (ms_marks_t *self, double t_s, uint32_t uav, const char *kind, const char *fmt,
                   ...)
{
    if (self->n == self->cap) {
        size_t cap = self->cap ? self->cap * 2 : 32;
        ms_mark_t *m = realloc (self->marks, cap * sizeof *m);
        if (!m)
            return -ENOMEM;
        self->marks = m;
        self->cap = cap;
    }
    ms_mark_t *m = &self->marks[self->n++];
    memset (m, 0, sizeof *m);
    m->t_s = t_s;
    m->uav_id = uav;
    snprintf (m->kind, sizeof m->kind, "%s", kind);
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (m->text, sizeof m->text, fmt, ap);
    va_end (ap);
    return 0;
}

int ms_marks_add (ms_marks_t *self, const Cgs__Intercept *m, double t_s)
{
    size_t k = 0;
    while (k < MS_MARKS_UAVS && self->last[k].seen && self->last[k].uav_id != m->uav_id)
        k++;
    if (k == MS_MARKS_UAVS)
        return 0; // more UAVs than followed: the first ones only
    __typeof__ (self->last[0]) *l = &self->last[k];
    const char *state = cgs_msg_enum_short (&cgs__intercept_state__descriptor, (int)m->state, "?");
    int rc = 0;
    bool first = !l->seen;
    if (m->designation_number != 0 && (first || m->designation_number != l->designation))
        rc = s_mark (self, t_s, m->uav_id, "designate", "designate track %u", m->track_id);
    else if (!first && m->designation_number == l->designation && m->track_id != l->track_id &&
             m->track_id && l->track_id)
        rc = s_mark (self, t_s, m->uav_id, "handover", "track %u to %u", l->track_id, m->track_id);
    if (rc == 0 && (first ? m->state != CGS__INTERCEPT_STATE__INTERCEPT_STATE_IDLE
                          : (int)m->state != l->state))
        rc = s_mark (
            self, t_s, m->uav_id,
            m->state == CGS__INTERCEPT_STATE__INTERCEPT_STATE_CANCELLED ? "cancel" : "phase",
            "%s%s%.60s", state, m->reason && *m->reason ? ": " : "", m->reason ? m->reason : "");
    if (rc == 0 && !first && m->designation_number == l->designation && m->replans > l->replans)
        rc = s_mark (self, t_s, m->uav_id, "replan", "re-plan %u", m->replans);
    l->seen = 1;
    l->uav_id = m->uav_id;
    l->designation = m->designation_number;
    l->track_id = m->track_id;
    l->replans = m->replans;
    l->state = (int)m->state;
    return rc;
}

void ms_marks_clear (ms_marks_t *self)
{
    free (self->marks);
    memset (self, 0, sizeof *self);
}
