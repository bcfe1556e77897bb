/* cgs_fault — checks and schedule of the debug-only fault channel. */
#include "cgs_fault.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>

const char *cgs_fault_name (Cgs__FaultAction a)
{
    switch (a) {
    case CGS__FAULT_ACTION__FAULT_ACTION_CRASH:
        return "crash";
    case CGS__FAULT_ACTION__FAULT_ACTION_HANG:
        return "hang";
    case CGS__FAULT_ACTION__FAULT_ACTION_SLOW:
        return "slow";
    default:
        return "?";
    }
}

int cgs_fault_request (cgs_fault_t *self, const Cgs__Fault *f, double now, char *why, size_t whylen)
{
    if (!f) {
        snprintf (why, whylen, "no fault given");
        return -EINVAL;
    }
    if (!isfinite (f->seconds) || f->seconds < 0 || f->seconds > CGS_FAULT_MAX_SECONDS) {
        snprintf (why, whylen, "seconds must be 0 (until the process ends) to %d, got %g",
                  CGS_FAULT_MAX_SECONDS, f->seconds);
        return -EINVAL;
    }
    switch (f->action) {
    case CGS__FAULT_ACTION__FAULT_ACTION_CRASH:
    case CGS__FAULT_ACTION__FAULT_ACTION_HANG:
        if (self->pending != CGS__FAULT_ACTION__FAULT_ACTION_UNSPECIFIED) {
            snprintf (why, whylen, "a %s is already pending", cgs_fault_name (self->pending));
            return -EINVAL;
        }
        self->pending = f->action;
        self->hang_s = f->seconds;
        break;
    case CGS__FAULT_ACTION__FAULT_ACTION_SLOW:
        if (f->stall_ms < 1 || f->stall_ms > CGS_FAULT_MAX_STALL) {
            snprintf (why, whylen, "a stall of 1 to %d ms in every %.0f ms, got %u ms",
                      CGS_FAULT_MAX_STALL, CGS_FAULT_PERIOD_S * 1e3, f->stall_ms);
            return -EINVAL;
        }
        self->stall_ms = f->stall_ms;
        self->slow_until = f->seconds > 0 ? now + f->seconds : 0;
        break;
    default:
        snprintf (why, whylen, "unknown fault action %d (crash, hang or slow)", (int)f->action);
        return -EINVAL;
    }
    self->requests++;
    return 0;
}

Cgs__FaultAction cgs_fault_take (cgs_fault_t *self, double *hang_s)
{
    Cgs__FaultAction a = self->pending;
    *hang_s = self->hang_s;
    self->pending = CGS__FAULT_ACTION__FAULT_ACTION_UNSPECIFIED;
    self->hang_s = 0;
    return a;
}

unsigned cgs_fault_stall_ms (cgs_fault_t *self, double now)
{
    if (self->stall_ms && self->slow_until > 0 && now >= self->slow_until)
        self->stall_ms = 0;
    return self->stall_ms;
}
