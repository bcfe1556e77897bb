/* cgs_fault — the debug-only fault channel, in the manner of Redis's DEBUG
 * SEGFAULT and DEBUG SLEEP: a service built with FAULT=1 (the test build is;
 * release builds are not) answers `mscgs fault INSTANCE ACTION` on
 * ipc://STATE_DIR/INSTANCE.fault, and after the reply it
 *   crash        aborts (dies of SIGABRT, as a crash would);
 *   hang [S]     blocks its event loop for S seconds (0: until killed): no
 *                messages, no commands, no watchdog, SIGTERM unheard;
 *   slow MS [S]  stalls its event loop MS ms (1..90) in every 100 ms for S
 *                seconds (0: until it ends).
 * This part is pure: it checks a request and keeps the schedule. The socket
 * and the actions are cgs_service's, compiled only with CGS_FAULT. */
#ifndef CGS_FAULT_H
#define CGS_FAULT_H

#include "cgs_msg.h"
#include <stdbool.h>
#include <stddef.h>

#define CGS_FAULT_PERIOD_S    0.1  // slow: one stall per period
#define CGS_FAULT_MAX_STALL   90   // ms, below the period: the loop still turns
#define CGS_FAULT_MAX_SECONDS 3600 // hang and slow at most an hour

typedef struct {
    Cgs__FaultAction pending; // crash or hang to do after the reply; UNSPECIFIED: none
    double hang_s;            // the pending hang's length, 0 = until killed
    unsigned stall_ms;        // slow: stall per period, 0 = not slowed
    double slow_until;        // slow: monotonic end, 0 = until the process ends
    unsigned long long requests;
} cgs_fault_t;

/* Take the request f at monotonic time now: 0, or -EINVAL with why. A crash
 * or a hang becomes pending (cgs_fault_take); a slow-down starts now. */
int cgs_fault_request (cgs_fault_t *self, const Cgs__Fault *f, double now, char *why,
                       size_t whylen);
/* The pending crash or hang, cleared (UNSPECIFIED when none); *hang_s its length. */
Cgs__FaultAction cgs_fault_take (cgs_fault_t *self, double *hang_s);
/* How long the loop stalls in the period starting at now; 0 once the slow-down ended. */
unsigned cgs_fault_stall_ms (cgs_fault_t *self, double now);
/* The action's name for the reply and logs ("crash", "hang", "slow", "?"). */
const char *cgs_fault_name (Cgs__FaultAction a);

#endif
