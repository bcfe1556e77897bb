/*
 * layers.js — the map (OpenLayers, global `ol`) in the exercise's local
 * east/north metre frame: its layers bottom to top, the view, the shaded
 * relief from the hello, and which layers the Sensors and Map Features
 * menus show.
 */
import { cgs } from './hooks.js';
import { S } from './symbols.js';

const FALLBACK_HALF_M = 500000;      // map extent without relief: ±500 km

// ---------------------------------------------------------------------------
// Layers (bottom to top)

// All vector layers draw into the map's one canvas. (A layer rendered to
// an image of its own, ol.layer.VectorImage, costs more to compose each
// time its content changes than plainly drawing the hits every update.)
function vectorLayer(name, style, extra, LayerClass) {
  // Features that move at every update skip the spatial index: rebalancing
  // it costs more than drawing the few thousand features outright.
  const opts = { source: new ol.source.Vector({ wrapX: false, useSpatialIndex: false }), style: style };
  if (extra) Object.assign(opts, extra);
  const layer = new (LayerClass || ol.layer.Vector)(opts);
  layer.set('name', name);
  return layer;
}

export const L = {
  relief: new ol.layer.Image({ source: null }),
  truth: vectorLayer('truth', null, { visible: false }),
  footprint: vectorLayer('footprint', null),
  sensorFootprint: vectorLayer('sensor-footprint', null),
  route: vectorLayer('route', null),
  hitsOld: vectorLayer('hits-old', S.hitOld),
  bcis: vectorLayer('bcis', function (f) {
    S.bcis.getText().setText(f.cgsLabel || '');
    return S.bcis;
  }),
  hitsCurrent: vectorLayer('hits-current', S.hitCurrent),
  target: vectorLayer('target', S.target),
  tracks: vectorLayer('tracks', null),
  uav: vectorLayer('uav', null),
};
L.relief.set('name', 'relief');

// Per-feature styles stored on the feature (`cgsStyle`), shared objects.
const featureStyle = (f) => f.cgsStyle;
L.truth.setStyle(featureStyle);
L.footprint.setStyle(featureStyle);
L.sensorFootprint.setStyle(featureStyle);
L.route.setStyle(featureStyle);
L.tracks.setStyle(featureStyle);
L.uav.setStyle(featureStyle);

export const src = {};
Object.keys(L).forEach((k) => { if (k !== 'relief') src[k] = L[k].getSource(); });

function makeView(extent) {
  const proj = new ol.proj.Projection({ code: 'CGS-LOCAL', units: 'm', extent: extent });
  const w = Math.max(ol.extent.getWidth(extent), ol.extent.getHeight(extent));
  return new ol.View({
    projection: proj,
    center: ol.extent.getCenter(extent),
    resolution: w / 1000,
    maxResolution: Math.max(w / 256, 50),
    minResolution: 0.05,
  });
}

export const map = new ol.Map({
  target: 'map',
  layers: [L.relief, L.truth, L.footprint, L.sensorFootprint, L.route, L.hitsOld, L.bcis, L.hitsCurrent,
    L.target, L.tracks, L.uav],
  controls: [new ol.control.Zoom(), new ol.control.ScaleLine({ units: 'metric' })],
  view: makeView([-FALLBACK_HALF_M, -FALLBACK_HALF_M, FALLBACK_HALF_M, FALLBACK_HALF_M]),
});
map.getView().setResolution(50);
cgs.map = map;

let reliefKey = null;      // url + extent of the relief shown
let viewFitted = false;    // the view was fitted once (first hello or first state)

// Relief and view from a hello: fit only the first time (or when the
// exercise's terrain changed), so the operator's pan and zoom survive a
// reconnect.
export function applyRelief(relief) {
  const ok = relief && typeof relief.url === 'string' && Array.isArray(relief.extent) &&
    relief.extent.length === 4 && relief.extent[2] > relief.extent[0] && relief.extent[3] > relief.extent[1];
  if (!ok) {
    if (reliefKey !== null) {
      L.relief.setSource(null);
      reliefKey = null;
    }
    return;
  }
  const key = relief.url + '|' + relief.extent.join(',');
  if (key === reliefKey) return;
  const extent = relief.extent.slice();
  const view = makeView(extent);
  map.setView(view);
  L.relief.setSource(new ol.source.ImageStatic({
    url: relief.url,
    imageExtent: extent,
    projection: view.getProjection(),
    interpolate: true,
  }));
  view.fit(extent, { size: map.getSize(), padding: [10, 10, 10, 10] });
  reliefKey = key;
  viewFitted = true;
}

// Without relief, the view centres on the first UAV once.
export function centreOnce(e, n) {
  if (viewFitted) return;
  map.getView().setCenter([e, n]);
  viewFitted = true;
}

// ---------------------------------------------------------------------------
// Visibility

// MTI in the Sensors menu hides every symbol the radar's hits give: the
// hits, the tracks and the designated target's marker; Show Tracks hides
// the tracks and the marker alone.
export function showMti(mti, tracks) {
  L.hitsOld.setVisible(mti);
  L.hitsCurrent.setVisible(mti);
  L.tracks.setVisible(mti && tracks);
  L.target.setVisible(mti && tracks);
}

// One of the other layers (bcis, route, truth) shown or hidden.
export function showLayer(name, visible) {
  L[name].setVisible(visible);
}
