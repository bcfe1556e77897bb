/*
 * geo.js — WGS 84 geodetic coordinates to the exercise's local east/north/
 * up frame in metres (the map's), as GeographicLib's LocalCartesian does it
 * on stationd's side: through geocentric (ECEF) coordinates, rotated to the
 * origin's tangent plane. Pure: no imports, no DOM.
 */

const A = 6378137;                   // WGS 84 semi-major axis, metres
const F = 1 / 298.257223563;         // flattening
const E2 = F * (2 - F);              // first eccentricity squared
const RAD = Math.PI / 180;

// Geocentric [x, y, z] of a latitude, longitude (degrees) and height above
// the ellipsoid (metres).
export function geocentric(latDeg, lonDeg, hM) {
  const phi = latDeg * RAD;
  const lam = lonDeg * RAD;
  const sp = Math.sin(phi);
  const cp = Math.cos(phi);
  const n = A / Math.sqrt(1 - E2 * sp * sp);
  return [(n + hM) * cp * Math.cos(lam), (n + hM) * cp * Math.sin(lam), (n * (1 - E2) + hM) * sp];
}

// The local frame about an origin: toEnu(lat, lon, h) is [east, north, up]
// in metres.
export function localFrame(latDeg, lonDeg, hM) {
  const o = geocentric(latDeg, lonDeg, hM);
  const sp = Math.sin(latDeg * RAD);
  const cp = Math.cos(latDeg * RAD);
  const sl = Math.sin(lonDeg * RAD);
  const cl = Math.cos(lonDeg * RAD);
  return {
    toEnu(lat, lon, h) {
      const p = geocentric(lat, lon, h);
      const dx = p[0] - o[0];
      const dy = p[1] - o[1];
      const dz = p[2] - o[2];
      return [
        -sl * dx + cl * dy,
        -sp * cl * dx - sp * sl * dy + cp * dz,
        cp * cl * dx + cp * sl * dy + sp * dz,
      ];
    },
  };
}
