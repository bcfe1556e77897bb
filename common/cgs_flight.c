/* cgs_flight — flight formulas (see cgs_flight.h). */
#include "cgs_flight.h"

#include <math.h>

double cgs_flight_turn_radius (double v_mps, double bank_deg)
{
    return v_mps * v_mps / (CGS_FLIGHT_G_MPS2 * tan (bank_deg * (M_PI / 180.0)));
}
