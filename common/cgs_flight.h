/* cgs_flight — the flight formulas more than one program needs: the radius
 * of a coordinated level turn, which uavsim flies and guidanced plans with.
 * Pure. */
#ifndef CGS_FLIGHT_H
#define CGS_FLIGHT_H

#define CGS_FLIGHT_G_MPS2 9.80665 // standard gravity, m/s²

/* The radius of a coordinated level turn at true airspeed v_mps banked
 * bank_deg: V² / (g·tan(bank)), metres. */
double cgs_flight_turn_radius (double v_mps, double bank_deg);

#endif
