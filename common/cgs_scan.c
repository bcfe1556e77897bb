/* cgs_scan — the azimuth scan schedule (see cgs_scan.h). */
#include "cgs_scan.h"

#include <errno.h>
#include <math.h>

double cgs_wrap360 (double a)
{
    a = fmod (a, 360.0);
    return a < 0 ? a + 360.0 : a;
}

int cgs_scan_init (const cgs_scan_params_t *p, cgs_scan_t *ret)
{
    if (!isfinite (p->beamwidth_deg) || p->beamwidth_deg <= 0 || p->beamwidth_deg > 360 ||
        !isfinite (p->rate_dps) || p->rate_dps <= 0)
        return -EINVAL;
    if (p->mode == CGS_SCAN_SECTOR &&
        (!isfinite (p->sector_center_deg) || !isfinite (p->sector_width_deg) ||
         p->sector_width_deg < p->beamwidth_deg || p->sector_width_deg > 360))
        return -EINVAL;
    if (p->mode != CGS_SCAN_FULL && p->mode != CGS_SCAN_SECTOR)
        return -EINVAL;
    cgs_scan_t s = {.p = *p};
    s.span_deg = p->mode == CGS_SCAN_FULL ? 360.0 : p->sector_width_deg;
    double d = floor (s.span_deg / p->beamwidth_deg + 1e-9);
    s.dwells = d < 1 ? 1 : (uint32_t)d;
    s.dwell_deg = s.span_deg / s.dwells;
    s.dwell_s = s.dwell_deg / p->rate_dps;
    *ret = s;
    return 0;
}

void cgs_scan_dwell (const cgs_scan_t *self, uint64_t k, double heading_deg, cgs_dwell_t *ret)
{
    uint64_t pass = k / self->dwells;
    uint32_t j = (uint32_t)(k % self->dwells);
    double w = self->dwell_deg, from, to;
    if (self->p.mode == CGS_SCAN_FULL) {
        from = j * w;
        to = from + w;
    } else {
        double c = self->p.sector_center_deg;
        if (self->p.sector_ref == CGS_SECTOR_HEADING)
            c += heading_deg;
        double lo = c - self->span_deg / 2;
        if (pass % 2 == 0) {
            from = lo + j * w;
            to = from + w;
        } else {
            from = lo + self->span_deg - j * w;
            to = from - w;
        }
    }
    *ret = (cgs_dwell_t){
        .index = k,
        .scan = (uint32_t)(pass + 1),
        .dwell = j,
        .dwells = self->dwells,
        .start_s = (double)k * self->dwell_s,
        .end_s = (double)(k + 1) * self->dwell_s,
        .az_from_deg = cgs_wrap360 (from),
        .az_to_deg = cgs_wrap360 (to),
        .az_center_deg = cgs_wrap360 ((from + to) / 2),
        .width_deg = w,
        .scan_start = j == 0,
        .scan_end = j + 1 == self->dwells,
    };
}

uint64_t cgs_scan_dwell_at (const cgs_scan_t *self, double t_s)
{
    double k = floor (t_s / self->dwell_s);
    return k >= 0 && k < 9e15 ? (uint64_t)k : 0; // NaN and negative times: 0
}

double cgs_dwell_lo_deg (const cgs_dwell_t *d)
{
    // Clockwise from az_from when the beam moves clockwise, else from az_to.
    double clockwise = cgs_wrap360 (d->az_to_deg - d->az_from_deg);
    return fabs (clockwise - d->width_deg) < 1e-6 ? d->az_from_deg : d->az_to_deg;
}

bool cgs_dwell_contains (const cgs_dwell_t *d, double az_deg)
{
    if (d->width_deg >= 360.0 - 1e-9)
        return true;
    return cgs_wrap360 (az_deg - cgs_dwell_lo_deg (d)) < d->width_deg;
}

cgs_pace_t cgs_scan_pace (const cgs_scan_t *self, cgs_scan_pace_t *pace, double t_s,
                          double history_s, uint64_t *ret_end, uint64_t *ret_skipped)
{
    uint64_t now = cgs_scan_dwell_at (self, t_s);
    *ret_skipped = 0;
    *ret_end = pace->next;
    if (!pace->started || now + 1 < pace->next) {
        cgs_pace_t why = pace->started ? CGS_PACE_BACK : CGS_PACE_START;
        pace->started = true;
        pace->next = now + 1;
        *ret_end = pace->next;
        return why;
    }
    uint64_t most = (uint64_t)(history_s / self->dwell_s);
    if (most > self->dwells)
        most = self->dwells;
    if (now > pace->next + most) {
        uint64_t skip = now - most - pace->next;
        pace->skipped += skip;
        pace->next += skip;
        *ret_skipped = skip;
    }
    *ret_end = now > pace->next ? now : pace->next;
    return CGS_PACE_RUN;
}
