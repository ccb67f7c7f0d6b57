// The ground station's web page, compiled into the binary so it works with no internet and no
// files beside the program: the HTML, its script (plain JavaScript drawing inline SVG) and its
// style sheet. The script draws the state that /events streams (GcsMapState's JSON).
#pragma once

#include <string_view>

namespace skyroute::web_assets {

inline constexpr std::string_view kIndexHtml = R"gcs(<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>skyroute ground station</title>
<link rel="stylesheet" href="gcs.css">
</head>
<body>
<header>
  <h1>skyroute ground station</h1>
  <span id="terrain"></span>
  <span class="spacer"></span>
  <span id="clock"></span>
  <span id="connection" class="down">connecting</span>
</header>
<main>
  <section id="map-panel" class="panel"><svg id="map" aria-label="map"></svg></section>
  <section id="profile-panel" class="panel">
    <h2 id="profile-title">Altitude profile</h2>
    <svg id="profile" aria-label="altitude profile"></svg>
  </section>
  <aside class="panel">
    <h2>Vehicles</h2>
    <table id="vehicles">
      <thead><tr><th></th><th>vehicle</th><th>revision</th><th>status</th><th>time</th></tr></thead>
      <tbody></tbody>
    </table>
    <p id="no-vehicles">No trajectory yet.</p>
    <h2>Obstacles</h2>
    <ul id="obstacles"></ul>
    <h2>No-fly zones</h2>
    <ul id="no-fly-zones"></ul>
    <h2>Legend</h2>
    <svg id="legend" viewBox="0 0 300 168" width="300" height="168"></svg>
  </aside>
</main>
<script src="gcs.js"></script>
</body>
</html>
)gcs";

inline constexpr std::string_view kStyle = R"gcs(:root { font: 14px/1.35 system-ui, "DejaVu Sans", sans-serif; color: #1d2330; background: #e9edf2; }
body { margin: 0; }
header { display: flex; align-items: baseline; gap: 16px; padding: 9px 14px; background: #1d2330; color: #fff; }
header h1 { font-size: 17px; margin: 0; font-weight: 600; }
#terrain { color: #b9c2d0; }
.spacer { flex: 1; }
#clock { font-variant-numeric: tabular-nums; color: #b9c2d0; }
#connection { padding: 1px 8px; border-radius: 9px; font-size: 12px; }
#connection.live { background: #2ea043; }
#connection.down { background: #b62324; }
main { display: grid; grid-template-columns: minmax(0, 1fr) 340px; grid-template-rows: minmax(0, 1fr) 250px;
       gap: 10px; padding: 10px; height: calc(100vh - 44px); box-sizing: border-box; }
.panel { background: #fff; border-radius: 6px; box-shadow: 0 1px 3px rgba(0, 0, 0, .18); padding: 8px; min-height: 0; }
#map-panel { grid-column: 1; grid-row: 1; }
#map { width: 100%; height: 100%; display: block; }
#profile-panel { grid-column: 1; grid-row: 2; display: flex; flex-direction: column; }
#profile { flex: 1; width: 100%; min-height: 0; display: block; }
aside { grid-column: 2; grid-row: 1 / span 2; overflow: auto; }
h2 { font-size: 12px; text-transform: uppercase; letter-spacing: .05em; color: #5a6272; margin: 6px 0 6px; }
#profile-title { text-transform: none; letter-spacing: 0; font-size: 14px; color: #1d2330; }
table { border-collapse: collapse; width: 100%; margin-bottom: 8px; }
th, td { padding: 4px 5px; text-align: left; border-bottom: 1px solid #e3e6eb; }
th { font-weight: 500; color: #5a6272; font-size: 12px; }
tbody tr { cursor: pointer; }
tr.selected { background: #eaf2ff; }
td.time { font-variant-numeric: tabular-nums; white-space: nowrap; }
.swatch { display: inline-block; width: 14px; height: 14px; border-radius: 50%; box-shadow: 0 0 0 2px #fff, 0 0 0 3px #8b93a1; }
.state { border-radius: 3px; padding: 1px 6px; font-size: 12px; background: #e3e6eb; }
.state.succeeded { background: #d3f2d9; color: #17602a; }
.state.replanned { background: #dbe8ff; color: #1b4aa0; }
.state.failed { background: #ffd9d6; color: #9d1c12; }
.state.accepted, .state.planning { background: #fff0c2; color: #7a5a00; }
.note { color: #9d1c12; font-size: 12px; }
ul { margin: 0 0 8px; padding-left: 18px; }
#no-vehicles { color: #5a6272; margin: 0 0 8px; }
svg text { font-family: system-ui, "DejaVu Sans", sans-serif; }
.halo { paint-order: stroke; stroke: #fff; stroke-width: 4px; stroke-linejoin: round; }
.map-label { font-size: 15px; font-weight: 700; }
.no-fly { fill: rgba(200, 0, 0, .18); stroke: #c00000; stroke-width: 2; }
.axis { font-size: 12px; fill: #5a6272; }
.grid { stroke: #e3e6eb; stroke-width: 1; }
)gcs";

inline constexpr std::string_view kScript = R"gcs(// Draws the ground station's state (streamed by /events as JSON) on the terrain image: trajectories
// with a marker at the current time, obstacles where the planner predicts them, no-fly zones, and
// the selected vehicle's altitude against the ground.
"use strict";

const SVG_NS = "http://www.w3.org/2000/svg";
const PALETTE = ["#d62728", "#1f5fd6", "#8e3fc9", "#e07b00", "#0f9aa8", "#d23a9b", "#6b4a2b", "#5b8c00"];
const OBSTACLE = "#ff7a00";

let state = null;     // the last state received
let view = null;      // the map's geometry (makeView)
let selected = null;  // the vehicle whose profile is shown
let profile = null;   // the profile's axes (drawProfile), for the time line

function node(ns, tag, attrs, parent, text) {
  const e = ns ? document.createElementNS(ns, tag) : document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  if (parent) parent.appendChild(e);
  return e;
}
const svg = (tag, attrs, parent, text) => node(SVG_NS, tag, attrs, parent, text);
const html = (tag, attrs, parent, text) => node(null, tag, attrs, parent, text);

// Ground metres per degree of latitude and of longitude at a latitude (WGS84 series).
function metresPerDegree(latDeg) {
  const p = latDeg * Math.PI / 180;
  return { lat: 111132.92 - 559.82 * Math.cos(2 * p) + 1.175 * Math.cos(4 * p),
           lon: 111412.84 * Math.cos(p) - 93.5 * Math.cos(3 * p) };
}

// The map image spans W x H units, a unit being one screen pixel and the same ground distance east
// and north (the image's grid is latitude/longitude, so it is stretched back by the metres per
// degree), as large as fits the panel.
function makeView(map, panel) {
  const m = metresPerDegree((map.south_deg + map.north_deg) / 2);
  const widthM = (map.east_deg - map.west_deg) * m.lon;
  const heightM = (map.north_deg - map.south_deg) * m.lat;
  const W = Math.max(200, Math.min(panel.clientWidth - 16, (panel.clientHeight - 16) * widthM / heightM));
  const H = W * heightM / widthM;
  return { W, H, m, metresPerUnit: widthM / W,
           x: lon => (lon - map.west_deg) / (map.east_deg - map.west_deg) * W,
           y: lat => (map.north_deg - lat) / (map.north_deg - map.south_deg) * H };
}

function colourOf(id) {
  const i = state.vehicles.findIndex(v => v.vehicle_id === id);
  return PALETTE[Math.max(0, i) % PALETTE.length];
}

// [i, f]: time t lies a fraction f of the way from utc[i] to utc[i + 1] (clamped to the ends).
function sampleAt(utc, t) {
  const last = utc.length - 1;
  if (t <= utc[0]) return [0, 0];
  if (t >= utc[last]) return [last, 0];
  let lo = 0, hi = last;
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (utc[mid] <= t) lo = mid; else hi = mid; }
  return [lo, (t - utc[lo]) / (utc[hi] - utc[lo])];
}
const lerp = (a, i, f) => (f === 0 ? a[i] : a[i] + (a[i + 1] - a[i]) * f);

function vehicleAt(traj, t) {
  const s = traj.samples, [i, f] = sampleAt(s.utc_ms, t);
  return { lat: lerp(s.lat_deg, i, f), lon: lerp(s.lon_deg, i, f), alt: lerp(s.alt_amsl_m, i, f) };
}

// The obstacle's centre as the planner predicts it: from -> to -> from ... at its speed.
function obstacleAt(o, t) {
  const a = o.track.from, b = o.track.to, m = view.m;
  const length = Math.hypot((b.lat_deg - a.lat_deg) * m.lat, (b.lon_deg - a.lon_deg) * m.lon);
  if (o.track.speed_mps <= 0 || length <= 0) return { lat: a.lat_deg, lon: a.lon_deg };
  const travelled = Math.max(0, t - o.track.start_utc_ms) / 1000 * o.track.speed_mps;
  const phase = travelled % (2 * length);
  const f = (phase <= length ? phase : 2 * length - phase) / length;
  return { lat: a.lat_deg + (b.lat_deg - a.lat_deg) * f, lon: a.lon_deg + (b.lon_deg - a.lon_deg) * f };
}
const obstacleLive = (o, t) => o.valid_until_utc_ms === null || t < o.valid_until_utc_ms;

function niceStep(span, count) {
  const raw = span / count, p = Math.pow(10, Math.floor(Math.log10(raw)));
  return [1, 2, 5, 10].map(k => k * p).find(s => s >= raw);
}
function clockText(seconds) {
  const s = Math.max(0, Math.round(seconds));
  return Math.floor(s / 60) + ":" + String(s % 60).padStart(2, "0");
}
const distanceText = m => (m >= 1000 ? (m / 1000) + " km" : m + " m");

function drawMap() {
  const svgRoot = document.getElementById("map");
  svgRoot.setAttribute("viewBox", `0 0 ${view.W} ${view.H}`);
  // The terrain stays while the drawing over it is redrawn: a new image element would load the
  // picture again at every state.
  const terrain = document.getElementById("terrain-image") ||
    svg("image", { id: "terrain-image", href: state.map.image, preserveAspectRatio: "none" }, svgRoot);
  for (const [k, v] of Object.entries({ x: 0, y: 0, width: view.W, height: view.H })) terrain.setAttribute(k, v);
  const old = document.getElementById("overlay");
  if (old) old.remove();
  const map = svg("g", { id: "overlay" }, svgRoot);
  const xy = (lat, lon) => `${view.x(lon).toFixed(1)},${view.y(lat).toFixed(1)}`;
  // Bottom to top: zones, obstacle tracks, trajectories, obstacles now, vehicles now (with labels).
  const layer = () => svg("g", {}, map);
  const zones = layer(), tracks = layer(), routes = layer(), bodies = layer(), vehicles = layer();

  for (const z of state.no_fly_zones) {
    svg("polygon", { class: "no-fly", points: z.ring.map(p => xy(p.lat_deg, p.lon_deg)).join(" ") }, zones);
  }
  for (const o of state.obstacles) {
    const a = o.track.from, b = o.track.to;
    svg("line", { x1: view.x(a.lon_deg), y1: view.y(a.lat_deg), x2: view.x(b.lon_deg), y2: view.y(b.lat_deg),
                  stroke: OBSTACLE, "stroke-width": 3, "stroke-dasharray": "10 7" }, tracks);
    const g = svg("g", { id: "obstacle-" + o.id, "data-obstacle": o.id }, bodies);
    const round = o.shape === "sphere" || o.shape === "cylinder";
    const rx = o.size_m[0] / view.metresPerUnit, ry = (round ? o.size_m[0] : o.size_m[1]) / view.metresPerUnit;
    const body = { fill: "rgba(255,122,0,0.35)", stroke: OBSTACLE, "stroke-width": 2.5 };
    if (o.shape === "box") svg("rect", { x: -rx, y: -ry, width: 2 * rx, height: 2 * ry, ...body }, g);
    else svg("ellipse", { rx, ry, ...body }, g);
    svg("text", { class: "map-label halo", "text-anchor": "middle", y: 6, fill: "#8a3b00" }, g, "#" + o.id);
  }
  for (const v of state.vehicles) {
    if (!v.trajectory) continue;
    const s = v.trajectory.samples, colour = colourOf(v.vehicle_id), chosen = v.vehicle_id === selected;
    const points = s.lat_deg.map((lat, i) => xy(lat, s.lon_deg[i])).join(" ");
    svg("polyline", { points, fill: "none", stroke: "#fff", "stroke-width": chosen ? 9 : 7, "stroke-opacity": 0.85,
                      "stroke-linejoin": "round" }, routes);
    const line = svg("polyline", { points, fill: "none", stroke: colour, "stroke-width": chosen ? 5 : 3.5,
                                   "stroke-linejoin": "round", "data-vehicle": v.vehicle_id }, routes);
    line.addEventListener("click", () => select(v.vehicle_id));
    const last = s.lat_deg.length - 1;
    svg("circle", { cx: view.x(s.lon_deg[0]), cy: view.y(s.lat_deg[0]), r: 7, fill: "#fff", stroke: colour, "stroke-width": 3 }, routes);
    svg("rect", { x: view.x(s.lon_deg[last]) - 7, y: view.y(s.lat_deg[last]) - 7, width: 14, height: 14, fill: "#fff",
                  stroke: colour, "stroke-width": 3 }, routes);
    const marker = svg("g", { id: "marker-" + v.vehicle_id }, vehicles);
    svg("circle", { r: 10, fill: colour, stroke: "#fff", "stroke-width": 3.5 }, marker);
    svg("text", { class: "map-label halo", x: 15, y: -12, fill: colour }, marker,
        `${v.vehicle_id} · rev ${v.trajectory.revision}`);
  }
  drawScaleAndNorth(map);
}

function drawScaleAndNorth(map) {
  const metres = niceStep(view.W * view.metresPerUnit, 4);
  const length = metres / view.metresPerUnit, x = 24, y = view.H - 24;
  svg("rect", { x: x - 12, y: y - 30, width: length + 56, height: 46, rx: 5, fill: "rgba(255,255,255,0.88)" }, map);
  svg("rect", { x, y, width: length / 2, height: 8, fill: "#1d2330" }, map);
  svg("rect", { x: x + length / 2, y, width: length / 2, height: 8, fill: "#fff", stroke: "#1d2330", "stroke-width": 1.5 }, map);
  svg("text", { x, y: y - 8, "font-size": 15 }, map, "0");
  svg("text", { x: x + length, y: y - 8, "font-size": 15, "text-anchor": "middle" }, map, distanceText(metres));
  const nx = view.W - 34, ny = 22;
  svg("path", { d: `M${nx},${ny} l11,30 l-11,-8 l-11,8 z`, fill: "#1d2330", stroke: "#fff", "stroke-width": 2 }, map);
  svg("text", { class: "map-label halo", x: nx, y: ny + 50, "text-anchor": "middle" }, map, "N");
}

function drawLegend() {
  const g = document.getElementById("legend");
  g.replaceChildren();
  const colour = state.vehicles.length ? colourOf(state.vehicles[0].vehicle_id) : PALETTE[0];
  const rows = [
    ["trajectory (colour per vehicle)", y => svg("line", { x1: 6, y1: y, x2: 40, y2: y, stroke: colour, "stroke-width": 4 }, g)],
    ["vehicle now · rev = revision", y => svg("circle", { cx: 23, cy: y, r: 8, fill: colour, stroke: "#fff", "stroke-width": 3 }, g)],
    ["start ○  end □", y => { svg("circle", { cx: 13, cy: y, r: 6, fill: "#fff", stroke: colour, "stroke-width": 3 }, g);
                              svg("rect", { x: 28, y: y - 6, width: 12, height: 12, fill: "#fff", stroke: colour, "stroke-width": 3 }, g); }],
    ["obstacle now", y => svg("ellipse", { cx: 23, cy: y, rx: 16, ry: 9, fill: "rgba(255,122,0,0.35)", stroke: OBSTACLE, "stroke-width": 2 }, g)],
    ["obstacle predicted track", y => svg("line", { x1: 6, y1: y, x2: 40, y2: y, stroke: OBSTACLE, "stroke-width": 3, "stroke-dasharray": "8 5" }, g)],
    ["no-fly zone", y => svg("rect", { x: 6, y: y - 8, width: 34, height: 16, class: "no-fly" }, g)],
    ["profile: ground under the path", y => svg("rect", { x: 6, y: y - 8, width: 34, height: 16, fill: "#b08a5c" }, g)],
  ];
  rows.forEach(([label, draw], i) => { const y = 14 + i * 23; draw(y); svg("text", { x: 52, y: y + 5, "font-size": 14 }, g, label); });
}

function drawSidebar() {
  const body = document.querySelector("#vehicles tbody");
  body.replaceChildren();
  for (const v of state.vehicles) {
    const row = html("tr", { "data-vehicle": v.vehicle_id, "data-revision": v.trajectory ? v.trajectory.revision : "" }, body);
    if (v.vehicle_id === selected) row.classList.add("selected");
    row.addEventListener("click", () => select(v.vehicle_id));
    html("span", { class: "swatch", style: "background:" + colourOf(v.vehicle_id) }, html("td", {}, row));
    html("td", {}, row, v.vehicle_id);
    html("td", { class: "revision" }, row, v.trajectory ? String(v.trajectory.revision) : "–");
    const status = html("td", {}, row);
    if (v.status) {
      html("span", { class: "state " + v.status.state }, status, v.status.state);
      if (v.status.error !== "none") html("div", { class: "note" }, status, v.status.field ? `${v.status.error}: ${v.status.field}` : v.status.error);
      if (v.status.message) status.title = v.status.message;
    } else {
      status.textContent = "–";
    }
    html("td", { class: "time", id: "time-" + v.vehicle_id }, row);
  }
  document.getElementById("no-vehicles").hidden = state.vehicles.length > 0;

  const obstacles = document.getElementById("obstacles");
  obstacles.replaceChildren();
  for (const o of state.obstacles) {
    const speed = o.track.speed_mps > 0 ? `, ${o.track.speed_mps} m/s ${o.motion.replaceAll("_", " ")}` : ", static";
    html("li", { "data-obstacle": o.id }, obstacles, `#${o.id} ${o.shape} ${o.size_m[0]} m${speed}`);
  }
  if (!state.obstacles.length) html("li", {}, obstacles, "none");
  const zones = document.getElementById("no-fly-zones");
  zones.replaceChildren();
  state.no_fly_zones.forEach((z, i) => html("li", {}, zones, `zone ${i + 1}: ${z.ring.length} corners`));
  if (!state.no_fly_zones.length) html("li", {}, zones, "none");
}

function drawProfile() {
  const p = document.getElementById("profile"), title = document.getElementById("profile-title");
  p.replaceChildren();
  profile = null;
  const v = state.vehicles.find(x => x.vehicle_id === selected && x.trajectory);
  if (!v) { title.textContent = "Altitude profile"; return; }
  const s = v.trajectory.samples, n = s.utc_ms.length;
  const W = p.clientWidth || 900, H = p.clientHeight || 200, left = 64, right = 14, top = 8, bottom = 26;
  p.setAttribute("viewBox", `0 0 ${W} ${H}`);
  const known = s.ground_amsl_m.filter(g => g !== null);
  let lo = Math.min(...s.alt_amsl_m, ...known), hi = Math.max(...s.alt_amsl_m, ...known);
  const step = niceStep(Math.max(hi - lo, 10), 4);
  lo = Math.floor(lo / step) * step; hi = Math.ceil(hi / step) * step;
  const t0 = s.utc_ms[0], span = Math.max(1, s.utc_ms[n - 1] - t0);
  const X = t => left + (t - t0) / span * (W - left - right);
  const Y = h => top + (hi - h) / (hi - lo) * (H - top - bottom);
  for (let h = lo; h <= hi + 1e-6; h += step) {
    svg("line", { class: "grid", x1: left, x2: W - right, y1: Y(h), y2: Y(h) }, p);
    svg("text", { class: "axis", x: left - 6, y: Y(h) + 4, "text-anchor": "end" }, p, `${h} m`);
  }
  const tStep = niceStep(span / 1000, 8) * 1000;
  for (let t = 0; t <= span; t += tStep) {
    svg("text", { class: "axis", x: X(t0 + t), y: H - 8, "text-anchor": "middle" }, p, clockText(t / 1000));
  }
  let ground = "";
  let clearance = { m: Infinity, i: -1 };
  for (let i = 0; i < n; ++i) {
    const g = s.ground_amsl_m[i];
    if (g === null) continue;
    ground += `${ground ? "L" : "M"}${X(s.utc_ms[i]).toFixed(1)},${Y(g).toFixed(1)} `;
    if (s.alt_amsl_m[i] - g < clearance.m) clearance = { m: s.alt_amsl_m[i] - g, i };
  }
  if (ground) {
    const first = s.ground_amsl_m.findIndex(g => g !== null), lastKnown = n - 1 - [...s.ground_amsl_m].reverse().findIndex(g => g !== null);
    svg("path", { d: `${ground}L${X(s.utc_ms[lastKnown])},${Y(lo)} L${X(s.utc_ms[first])},${Y(lo)} Z`, fill: "#b08a5c" }, p);
  }
  const colour = colourOf(v.vehicle_id);
  svg("polyline", { points: s.alt_amsl_m.map((h, i) => `${X(s.utc_ms[i]).toFixed(1)},${Y(h).toFixed(1)}`).join(" "),
                    fill: "none", stroke: colour, "stroke-width": 2.5 }, p);
  if (clearance.i >= 0) {
    const cx = X(s.utc_ms[clearance.i]), cy = Y(s.alt_amsl_m[clearance.i]);
    svg("line", { x1: cx, x2: cx, y1: cy, y2: Y(s.ground_amsl_m[clearance.i]), stroke: "#1d2330", "stroke-dasharray": "3 3" }, p);
  }
  svg("line", { id: "profile-now", y1: top, y2: H - bottom, stroke: "#1d2330", "stroke-width": 1.5 }, p);
  svg("circle", { id: "profile-dot", r: 5, fill: colour, stroke: "#fff", "stroke-width": 2 }, p);
  profile = { vehicle: v, t0, t1: t0 + span, X, Y };
  const minClearance = clearance.i >= 0 ? ` · lowest ${Math.round(clearance.m)} m above ground (dashed)` : "";
  title.textContent = `Altitude profile of ${v.vehicle_id}, revision ${v.trajectory.revision} · ` +
    `m AMSL over m:ss since the revision began${minClearance}`;
}

// Moves what depends on the time: vehicle markers, obstacles, the profile's time line, clocks.
function tick() {
  if (!state) return;
  const now = Date.now();
  document.getElementById("clock").textContent = new Date(now).toISOString().slice(11, 19) + " UTC";
  for (const v of state.vehicles) {
    if (!v.trajectory) continue;
    const marker = document.getElementById("marker-" + v.vehicle_id), at = vehicleAt(v.trajectory, now);
    if (marker) marker.setAttribute("transform", `translate(${view.x(at.lon).toFixed(1)},${view.y(at.lat).toFixed(1)})`);
    const cell = document.getElementById("time-" + v.vehicle_id), t = v.trajectory;
    if (cell) cell.textContent = now < t.start_utc_ms ? "starts in " + clockText((t.start_utc_ms - now) / 1000)
                                : now > t.end_utc_ms ? "arrived" : clockText((t.end_utc_ms - now) / 1000) + " left";
  }
  for (const o of state.obstacles) {
    const g = document.getElementById("obstacle-" + o.id);
    if (!g) continue;
    const at = obstacleAt(o, now);
    g.setAttribute("transform", `translate(${view.x(at.lon).toFixed(1)},${view.y(at.lat).toFixed(1)})`);
    g.style.display = obstacleLive(o, now) ? "" : "none";
  }
  if (profile) {
    const t = Math.min(Math.max(now, profile.t0), profile.t1), x = profile.X(t);
    const line = document.getElementById("profile-now"), dot = document.getElementById("profile-dot");
    line.setAttribute("x1", x); line.setAttribute("x2", x);
    dot.setAttribute("cx", x); dot.setAttribute("cy", profile.Y(vehicleAt(profile.vehicle.trajectory, t).alt));
  }
}

function select(id) {
  selected = id;
  render();
}

function render() {
  if (!selected || !state.vehicles.some(v => v.vehicle_id === selected && v.trajectory)) {
    const first = state.vehicles.find(v => v.trajectory);
    selected = first ? first.vehicle_id : null;
  }
  view = makeView(state.map, document.getElementById("map-panel"));
  drawMap();
  drawSidebar();
  drawLegend();
  drawProfile();
  tick();
}

function receive(next) {
  state = next;
  const m = state.map;
  const deg = (d, pos, neg) => `${Math.abs(d).toFixed(3)}° ${d >= 0 ? pos : neg}`;
  document.getElementById("terrain").textContent = `${m.terrain}: ${deg(m.south_deg, "N", "S")} to ${deg(m.north_deg, "N", "S")}, ` +
    `${deg(m.west_deg, "E", "W")} to ${deg(m.east_deg, "E", "W")}`;
  document.body.dataset.stateVersion = state.version;
  render();
}

function connect() {
  const status = document.getElementById("connection");
  const events = new EventSource("events");
  events.onopen = () => { status.textContent = "live"; status.className = "live"; };
  events.onerror = () => {
    status.textContent = "reconnecting"; status.className = "down";
    // EventSource retries a dropped stream itself, but not a refused one (503: the server's
    // streams are all taken): then try again a little later.
    if (events.readyState === EventSource.CLOSED) setTimeout(connect, 5000);
  };
  events.onmessage = e => receive(JSON.parse(e.data));
}

connect();
setInterval(tick, 250);
window.addEventListener("resize", () => state && render());
)gcs";

}  // namespace skyroute::web_assets
