#pragma once
// The page of effigi render --preview (preview_server.cpp serves it at /): one HTML file
// with its style, script and chart (inline SVG) inside, nothing fetched from elsewhere, so
// it works without a network. Every second it polls /status.json and, when a pass has
// ended since, loads /image.png?frame=N&exposure=E&tonemap=T into a fresh image that
// replaces the shown one once decoded (no flicker). The exposure slider and the tone map
// only change that query: the server exposes and tone maps the linear image as hdrfilm's
// PNG does. The chart plots the renderer's relMSE estimate against rendering time on log
// axes, with the ideal Monte Carlo slope (relMSE ∝ 1/t) through the last point.
//
// Layout: at a window of 800 × 600 the image box is 512 × 512 at (16, 64) (tests/
// test_preview.cpp looks there in Chromium's screenshot); it grows with larger windows.

namespace effigi::app {

inline constexpr const char* PreviewPage = R"page(<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>effigi preview</title>
<link rel="icon" href="data:,">
<style>
  :root { color-scheme: dark; }
  body { margin: 0; background: #15171a; color: #d8dadc; font: 14px/1.45 system-ui, sans-serif; }
  header { height: 48px; box-sizing: border-box; padding: 12px 16px; background: #0c0d0f; display: flex;
           gap: 12px; align-items: baseline; white-space: nowrap; overflow: hidden; }
  header b { font-size: 16px; color: #fff; }
  #scene { color: #9aa0a6; overflow: hidden; text-overflow: ellipsis; }
  main { display: flex; gap: 16px; padding: 16px; align-items: flex-start; }
  #view { flex: none; width: max(512px, min(100vw - 400px, 100vh - 96px)); aspect-ratio: 1; background: #202226;
          display: flex; }
  #img { width: 100%; height: 100%; object-fit: contain; image-rendering: pixelated; }
  #panel { flex: 1 1 0; min-width: 0; }
  .row { display: flex; gap: 8px; align-items: center; }
  progress { flex: 1; height: 14px; accent-color: #6ab0ff; }
  table { border-collapse: collapse; margin: 8px 0 12px; width: 100%; table-layout: fixed; }
  td { padding: 2px 0; vertical-align: top; }
  td:first-child { color: #9aa0a6; width: 108px; white-space: nowrap; }
  h2 { font-size: 13px; font-weight: 600; margin: 8px 0 4px; color: #c0c4c8; }
  svg { width: 100%; background: #1c1e22; }
  svg text { fill: #9aa0a6; font-size: 10px; }
  .grid { stroke: #33363b; stroke-width: 1; }
  .curve { fill: none; stroke: #6ab0ff; stroke-width: 1.6; }
  .ideal { stroke: #888; stroke-width: 1; stroke-dasharray: 2 3; }
  .target { stroke: #e8a33d; stroke-width: 1; stroke-dasharray: 5 3; }
  label { display: flex; gap: 8px; align-items: center; margin-top: 10px; }
  input[type=range] { flex: 1; min-width: 0; }
  #ev { width: 3.2em; text-align: right; }
  #state.ended { color: #e8a33d; }
</style>
</head>
<body>
<header><b>effigi</b><span id="renderer"></span><span id="scene"></span></header>
<main>
  <div id="view"><img id="img" alt=""></div>
  <section id="panel">
    <div class="row"><progress id="bar" max="1" value="0"></progress><span id="pct"></span></div>
    <table>
      <tr><td>state</td><td id="state">connecting</td></tr>
      <tr><td>samples/pixel</td><td id="spp">–</td></tr>
      <tr><td>time</td><td id="time">–</td></tr>
      <tr><td>ETA</td><td id="eta">–</td></tr>
      <tr><td>speed</td><td id="rate">–</td></tr>
      <tr><td>relMSE (est.)</td><td id="relmse">–</td></tr>
      <tr><td>image</td><td id="size">–</td></tr>
    </table>
    <h2>estimated relMSE vs time</h2>
    <svg id="chart" viewBox="0 0 320 200"></svg>
    <label>exposure <input id="exposure" type="range" min="-8" max="8" step="0.25" value="0">
      <span id="ev">+0.00</span></label>
    <label>tone map <select id="tonemap"><option>none</option><option>reinhard</option><option>filmic</option>
      </select></label>
  </section>
</main>
<script>
"use strict";
const $ = (id) => document.getElementById(id);
let frame = 0, shown = "", loading = false, done = false, failures = 0;

function duration(s) {
  if (s == null) return "–";
  if (s < 60) return s.toFixed(s < 10 ? 1 : 0) + " s";
  const m = Math.floor(s / 60), h = Math.floor(m / 60);
  return h > 0 ? `${h} h ${m % 60} min` : `${m} min ${Math.round(s % 60)} s`;
}
const rate = (x) => x == null ? "–" : x >= 1e6 ? (x / 1e6).toFixed(2) + " M" : x >= 1e3 ? (x / 1e3).toFixed(1) + " k"
                                              : x.toFixed(0);
const sci = (x) => x == null ? "–" : x.toExponential(2);

function imageUrl() {
  return `/image.png?frame=${frame}&exposure=${$("exposure").value}&tonemap=${$("tonemap").value}`;
}

// A new image replaces the shown one only once decoded; one load at a time.
function refreshImage() {
  if (frame < 1 || loading) return;
  const url = imageUrl();
  if (url === shown) return;
  loading = true;
  const next = new Image();
  next.id = "img";
  next.alt = "the render so far";
  next.onload = () => { $("img").replaceWith(next); shown = url; loading = false; refreshImage(); };
  next.onerror = () => { loading = false; };
  next.src = url;
}

// relMSE against seconds, log-log, decades as grid lines.
function chart(history, target) {
  const W = 320, H = 200, L = 44, R = 16, T = 10, B = 26, svg = $("chart");
  const pts = history.filter((p) => p[0] > 0 && p[1] > 0);
  if (pts.length === 0) {
    svg.innerHTML = `<text x="${W / 2}" y="${H / 2}" text-anchor="middle">no estimate yet</text>`;
    return;
  }
  const lx = pts.map((p) => Math.log10(p[0])), ly = pts.map((p) => Math.log10(p[1]));
  if (target > 0) ly.push(Math.log10(target));
  let x0 = Math.floor(Math.min(...lx)), x1 = Math.ceil(Math.max(...lx));
  let y0 = Math.floor(Math.min(...ly)), y1 = Math.ceil(Math.max(...ly));
  if (x1 <= x0) x1 = x0 + 1;
  if (y1 <= y0) y1 = y0 + 1;
  const X = (v) => (L + (Math.log10(v) - x0) / (x1 - x0) * (W - L - R)).toFixed(1);
  const Y = (v) => (T + (y1 - Math.log10(v)) / (y1 - y0) * (H - T - B)).toFixed(1);
  let s = `<clipPath id="plot"><rect x="${L}" y="${T}" width="${W - L - R}" height="${H - T - B}"/></clipPath>`;
  for (let k = x0; k <= x1; ++k) {
    const x = X(10 ** k), label = k >= 0 ? String(10 ** k) : (10 ** k).toFixed(-k);
    s += `<line class="grid" x1="${x}" y1="${T}" x2="${x}" y2="${H - B}"/>`;
    s += `<text x="${x}" y="${H - B + 12}" text-anchor="middle">${label} s</text>`;
  }
  for (let k = y0; k <= y1; ++k) {
    const y = Y(10 ** k);
    s += `<line class="grid" x1="${L}" y1="${y}" x2="${W - R}" y2="${y}"/>`;
    s += `<text x="${L - 4}" y="${+y + 3}" text-anchor="end">1e${k}</text>`;
  }
  const [tl, el] = pts[pts.length - 1], ta = 10 ** x0, tb = 10 ** x1;
  s += `<line class="ideal" clip-path="url(#plot)" x1="${X(ta)}" y1="${Y(el * tl / ta)}" x2="${X(tb)}"` +
       ` y2="${Y(el * tl / tb)}"><title>ideal Monte Carlo convergence, relMSE ∝ 1/t</title></line>`;
  if (target > 0)
    s += `<line class="target" x1="${L}" y1="${Y(target)}" x2="${W - R}" y2="${Y(target)}">` +
         `<title>target ${sci(target)}</title></line>`;
  s += `<polyline class="curve" points="${pts.map((p) => X(p[0]) + "," + Y(p[1])).join(" ")}"/>`;
  s += `<circle cx="${X(tl)}" cy="${Y(el)}" r="2.5" fill="#6ab0ff"/>`;
  s += `<text x="${W - R - 4}" y="${T + 12}" text-anchor="end">rendering time →</text>`;
  svg.innerHTML = s;
}

function update(s) {
  const name = s.scene.split("/").pop();
  document.title = `effigi ${s.progress == null ? "" : Math.round(100 * s.progress) + " % "}· ${name}`;
  $("scene").textContent = s.scene;
  $("renderer").textContent = s.renderer;
  if (s.progress == null) $("bar").removeAttribute("value"); else $("bar").value = s.progress;
  $("pct").textContent = s.progress == null ? "" : (100 * s.progress).toFixed(0) + " %";
  $("state").textContent = s.done ? (s.interrupted ? "interrupted" : "finished") : "rendering";
  $("spp").textContent = s.spp + (s.target.spp ? ` of ${s.target.spp}` : "");
  $("time").textContent = duration(s.seconds) + (s.target.seconds ? ` of ${duration(s.target.seconds)}` : "");
  $("eta").textContent = s.done ? "–" : duration(s.eta);
  $("rate").textContent = rate(s.samplesPerSecond) + " samples/s";
  $("relmse").textContent = sci(s.relmse) + (s.target.relmse ? ` (target ${sci(s.target.relmse)})` : "");
  $("size").textContent = `${s.width} × ${s.height}`;
  chart(s.history, s.target.relmse);
  if (s.frame !== frame) { frame = s.frame; refreshImage(); }
  done = s.done;
}

async function poll() {
  try {
    const r = await fetch("/status.json", { cache: "no-store" });
    if (!r.ok) throw new Error(`status ${r.status}`);
    update(await r.json());
    failures = 0;
  } catch (e) {
    if (++failures >= 3) {
      $("state").textContent = "ended (the render has exited)";
      $("state").className = "ended";
      return;
    }
  }
  if (!done) setTimeout(poll, 1000);
}

$("exposure").addEventListener("input", () => {
  const e = +$("exposure").value;
  $("ev").textContent = (e < 0 ? "" : "+") + e.toFixed(2);
  refreshImage();
});
$("tonemap").addEventListener("change", refreshImage);
poll();
</script>
</body>
</html>
)page";

} // namespace effigi::app
