// index.html of shadowkit-report: the plots and tables drawn from REPORT (the data literal that
// samples/report/html_writer.cpp writes above this script) and the image viewer. No library and no
// network: SVG built here, images by relative path, so the page opens from file://.
"use strict";

const FAMILY_TITLES = {
  shadow_map: "shadow map", warp: "warped maps and cascades", soft: "PCF, PCSS, bias study, sampled area light",
  volume: "shadow volumes", smoothie: "smoothies", wedge: "penumbra wedges",
  omni: "point lights: cube and dual-paraboloid maps", silmap: "silhouette maps", linear: "linear (tube) lights",
  prefilter: "pre-filtered maps: VSM, ESM, EVSM, MSM", cache: "cached shadow maps", check: "instrument check"
};
const PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf",
                 "#7f7f7f", "#bcbd22", "#00008b", "#000000", "#ff1493", "#556b2f", "#a0522d", "#20b2aa"];
const SVG_NS = "http://www.w3.org/2000/svg";

const rows = REPORT.rows;
rows.forEach((r, i) => { r.index = i; });
const scenes = REPORT.scenes;
const families = [...new Set(rows.map(r => r.family))];
const familyColor = Object.fromEntries(families.map((f, i) => [f, PALETTE[i % PALETTE.length]]));

// ------------------------------------------------------------------ small helpers

function el(tag, attrs, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === "text") e.textContent = v;
    else if (k === "html") e.innerHTML = v;
    else if (k.startsWith("on")) e.addEventListener(k.slice(2), v);
    else e.setAttribute(k, v);
  }
  for (const c of children) e.append(c);
  return e;
}

function svgEl(tag, attrs) {
  const e = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  return e;
}

// Text for innerHTML (scene names come from mesh file names).
function esc(t) { return String(t).replace(/[&<>"]/g, c => ({"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;"})[c]); }
function fmt(v, digits) { return v === null || v === undefined ? "-" : Number(v).toFixed(digits); }
function pct(v) { return v === null || v === undefined ? "-" : (100 * v).toFixed(1) + "%"; }
function pct3(v) { return v === null || v === undefined ? "-" : +(100 * v).toPrecision(3) + "%"; }
function familyTitle(f) { return FAMILY_TITLES[f] || f; }
function sceneId(name) { return "scene-" + name.replace(/[^A-Za-z0-9_-]/g, "_"); }
function okRows(scene) { return rows.filter(r => r.scene === scene && !r.failed); }

function bestOf(list) {
  return list.reduce((best, r) => (!best || r.rmse < best.rmse ? r : best), null);
}

function rowLabel(r) { return r.technique + (r.settings ? " " + r.settings : ""); }

// A link that opens a row in the viewer; hidden by the filters like the row's plot point.
function rowLink(r, text) {
  return el("button", {type: "button", class: "row", "data-row": r.index, text: text, onclick: () => openRow(r.index)});
}

function rowSummary(r) { return rowLabel(r) + " (" + fmt(r.rmse, 4) + ", " + fmt(r.ms, 2) + " ms)"; }

// ------------------------------------------------------------------ filters

const filter = {families: new Set(families), hardness: "all", settings: "all"};

function rowVisible(r) {
  if (!filter.families.has(r.family)) return false;
  if (filter.hardness !== "all" && (filter.hardness === "hard") !== r.hard) return false;
  if (filter.settings !== "all" && (filter.settings === "default") !== r.def) return false;
  return true;
}

function applyFilters() {
  for (const e of document.querySelectorAll("[data-row]")) e.classList.toggle("off", !rowVisible(rows[+e.dataset.row]));
}

function buildFilters() {
  const box = document.getElementById("filter-families");
  for (const f of families) {
    const input = el("input", {type: "checkbox", checked: "", value: f});
    input.addEventListener("change", () => {
      if (input.checked) filter.families.add(f); else filter.families.delete(f);
      applyFilters();
    });
    box.append(el("label", {title: familyTitle(f)}, input, el("span", {class: "swatch", style: "background:" + familyColor[f]}), f));
  }
  for (const name of ["hardness", "settings"])
    for (const input of document.querySelectorAll(`input[name=${name}]`))
      input.addEventListener("change", () => { filter[name] = input.value; applyFilters(); });
}

// ------------------------------------------------------------------ plots

// A scatter plot: opts.points [{x, y, color, row, ring, big, tip}], opts.lines [{points: [[x, y]], color, dash, step}],
// opts.xlog, opts.xlabel, opts.ylabel. Returns the <svg>.
function plot(opts) {
  const W = 520, H = 320, m = {l: 56, r: 20, t: 10, b: 40};
  const s = svgEl("svg", {class: "plot", width: W, height: H, viewBox: `0 0 ${W} ${H}`});
  const xs = opts.points.map(p => p.x), ys = opts.points.map(p => p.y);
  const X = axisScale(xs, opts.xlog, m.l, W - m.r);
  const Y = axisScale(ys, false, H - m.b, m.t);
  s.append(svgEl("rect", {x: m.l, y: m.t, width: W - m.l - m.r, height: H - m.t - m.b, fill: "#fff", stroke: "#444"}));
  drawTicks(s, X, true, m.t, H - m.b);
  drawTicks(s, Y, false, m.l, W - m.r);
  s.append(text(svgEl("text", {x: (m.l + W - m.r) / 2, y: H - 6, "text-anchor": "middle"}), opts.xlabel));
  s.append(text(svgEl("text", {x: 12, y: (m.t + H - m.b) / 2, "text-anchor": "middle",
                               transform: `rotate(-90 12 ${(m.t + H - m.b) / 2})`}), opts.ylabel));
  for (const line of opts.lines || []) s.append(polyline(line, X, Y));
  for (const p of opts.points) s.append(point(p, X, Y));
  return s;
}

function text(e, t) { e.textContent = t; return e; }

// Maps values to pixels [a, b]: linear from 0, or log10 over whole decades. .ticks: the values to label.
function axisScale(values, log, a, b) {
  const v = values.filter(x => Number.isFinite(x));
  if (log) {
    const pos = v.filter(x => x > 0);
    let lo = Math.floor(Math.log10(Math.min(...pos, 1))), hi = Math.ceil(Math.log10(Math.max(...pos, 1)));
    if (hi <= lo) hi = lo + 1;
    const f = x => a + (Math.log10(Math.max(x, 1e-6)) - lo) / (hi - lo) * (b - a);
    f.ticks = [];
    for (let d = lo; d <= hi; ++d) f.ticks.push(Math.pow(10, d));
    return f;
  }
  const hi = (Math.max(...v, 0) || 1) * 1.1;
  const f = x => a + x / hi * (b - a);
  f.ticks = [0, 1, 2, 3, 4].map(k => hi * k / 4);
  return f;
}

function drawTicks(s, scale, vertical, from, to) {
  for (const t of scale.ticks) {
    const p = scale(t);
    const label = t === 0 ? "0" : t >= 1 ? String(+t.toPrecision(3)) : t.toPrecision(2);
    if (vertical) {
      s.append(svgEl("line", {x1: p, y1: from, x2: p, y2: to, stroke: "#ddd"}));
      s.append(text(svgEl("text", {x: p, y: to + 14, "text-anchor": "middle"}), label));
    } else {
      s.append(svgEl("line", {x1: from, y1: p, x2: to, y2: p, stroke: "#eee"}));
      s.append(text(svgEl("text", {x: from - 4, y: p + 4, "text-anchor": "end"}), label));
    }
  }
}

function polyline(line, X, Y) {
  const pts = [];
  line.points.forEach(([x, y], k) => {
    if (line.step && k > 0) pts.push(X(x) + "," + Y(line.points[k - 1][1]));
    pts.push(X(x) + "," + Y(y));
  });
  return svgEl("polyline", {points: pts.join(" "), fill: "none", stroke: line.color,
                            "stroke-width": line.dash ? 1 : 1.5, "stroke-dasharray": line.dash ? "4 3" : "none"});
}

function point(p, X, Y) {
  const g = svgEl("g", p.row !== undefined ? {"data-row": p.row} : {});
  const cx = X(p.x), cy = Y(p.y);
  if (p.big) g.append(svgEl("circle", {cx, cy, r: 7, fill: "none", stroke: "#000"}));
  const c = svgEl("circle", {class: "pt", cx, cy, r: 4, fill: p.color, "fill-opacity": 0.85,
                             stroke: p.ring ? "#000" : "none", "stroke-width": 1.5});
  if (p.row !== undefined) c.dataset.row = p.row;
  c.addEventListener("mousemove", e => showTip(e, p.tip));
  c.addEventListener("mouseleave", hideTip);
  if (p.row !== undefined) c.addEventListener("click", () => openRow(p.row));
  g.append(c);
  return g;
}

// ------------------------------------------------------------------ tooltip

function rowTip(r) {
  return `<b>${esc(r.technique)}</b> ${esc(r.settings || "(no settings)")}<br>RMSE ${fmt(r.rmse, 4)}, penumbra RMSE ` +
         `${fmt(r.penumbra_rmse, 4)}, leak ${pct(r.leak)}<br>${fmt(r.ms, 2)} ms, ${fmt(r.mib, 2)} MiB` +
         `${r.pareto ? "<br>on the Pareto front" : ""}`;
}

function showTip(e, html) {
  const tip = document.getElementById("tooltip");
  tip.innerHTML = html;
  tip.hidden = false;
  tip.style.left = Math.min(e.clientX + 14, window.innerWidth - tip.offsetWidth - 4) + "px";
  tip.style.top = (e.clientY + 14) + "px";
}

function hideTip() { document.getElementById("tooltip").hidden = true; }

// ------------------------------------------------------------------ the image viewer

const viewer = {row: null, mode: "side", zoom: 1, syncing: false};

function openRow(i, show = true) {
  const r = rows[i];
  viewer.row = r;
  document.getElementById("v-title").textContent = `${r.scene}: ${rowLabel(r)}`;
  document.getElementById("v-metrics").innerHTML = rowTip(r).replace(/<br>/g, " · ").replace(/<\/?b>/g, "") +
    ` · family ${r.family} (${familyTitle(r.family)})`;
  const src = {reference: r.images.reference, technique: r.images.technique, error: r.images.error};
  for (const kind of ["reference", "technique", "error"]) document.getElementById("img-" + kind).src = src[kind];
  document.getElementById("slide-reference").src = src.reference;
  document.getElementById("slide-technique").src = src.technique;
  updateSiblingButtons(r);
  setZoom(viewer.zoom);
  if (show) document.getElementById("viewer").hidden = false;
}

// The technique's default and best rows on the same scene.
function siblings(r) {
  const same = okRows(r.scene).filter(o => o.technique === r.technique);
  return {def: same.find(o => o.def), best: bestOf(same)};
}

function updateSiblingButtons(r) {
  const s = siblings(r);
  for (const [id, target] of [["v-default", s.def], ["v-best", s.best]]) {
    const b = document.getElementById(id);
    b.disabled = !target || target === r;
    b.onclick = () => target && openRow(target.index);
  }
}

function setMode(mode) {
  viewer.mode = mode;
  const panes = document.getElementById("v-panes");
  panes.className = mode === "side" ? "" : mode === "slider" ? "slider" : "single";
  for (const fig of panes.querySelectorAll("figure")) {
    const kind = fig.dataset.kind;
    fig.hidden = mode === "side" ? kind === "slider" : kind !== mode;
  }
  for (const b of document.querySelectorAll("#v-modes button")) b.classList.toggle("active", b.dataset.mode === mode);
}

function setZoom(z) {
  viewer.zoom = z;
  const w = REPORT.info.width * z, h = REPORT.info.height * z;
  for (const img of document.querySelectorAll("#v-panes img")) {
    img.style.width = w + "px";
    img.style.height = h + "px";
  }
  setWipe();
}

function setWipe() {
  const v = +document.getElementById("v-wipe").value;
  document.querySelector(".wipe-clip").style.width = (REPORT.info.width * viewer.zoom * v / 100) + "px";
}

// Side by side, the panes scroll together (the same pixels in all three when zoomed).
function syncScroll(from) {
  if (viewer.syncing) return;
  viewer.syncing = true;
  for (const s of document.querySelectorAll("#v-panes .scroll"))
    if (s !== from) { s.scrollLeft = from.scrollLeft; s.scrollTop = from.scrollTop; }
  viewer.syncing = false;
}

function buildViewer() {
  for (const b of document.querySelectorAll("#v-modes button")) b.addEventListener("click", () => setMode(b.dataset.mode));
  document.getElementById("v-zoom").addEventListener("change", e => setZoom(+e.target.value));
  document.getElementById("v-wipe").addEventListener("input", setWipe);
  document.getElementById("v-close").addEventListener("click", () => { document.getElementById("viewer").hidden = true; });
  document.addEventListener("keydown", e => { if (e.key === "Escape") document.getElementById("viewer").hidden = true; });
  for (const s of document.querySelectorAll("#v-panes .scroll")) s.addEventListener("scroll", () => syncScroll(s));
  setMode("side");
  // small images (--quick: 256x192) start at 2x
  const zoom = REPORT.info.width <= 320 ? 2 : 1;
  document.getElementById("v-zoom").value = String(zoom);
  viewer.zoom = zoom;
  // the images are there before the first click: the first scene's most accurate row
  const first = scenes.map(sc => bestOf(okRows(sc.name))).find(r => r);
  if (first) openRow(first.index, false);
}

// ------------------------------------------------------------------ sections

function buildRunInfo() {
  const i = REPORT.info;
  document.getElementById("run").textContent = `${i.renderer}; ${i.cpu}; ${i.date}; ${i.width}x${i.height}` +
    `${i.quick ? "; --quick run" : ""}; ${rows.length} rows on ${scenes.length} scenes; command: ${i.command}`;
  const nav = document.getElementById("nav");
  for (const [id, label] of [["summary", "best"], ["families", "families"], ["scenes", "scenes"],
                             ["light-size", "light size"], ["flicker", "flicker"], ["light-sweep", "light sweep"]])
    nav.append(el("a", {href: "#" + id, text: label}));
  for (const sc of scenes.filter(s => !s.base)) nav.append(el("a", {href: "#" + sceneId(sc.name), text: sc.name}));
}

function buildBestPerScene() {
  const table = el("table", {}, el("tr", {html: "<th>scene</th><th>most accurate</th><th>Pareto front, fastest first</th>"}));
  for (const sc of scenes) {
    const ok = okRows(sc.name);
    const best = bestOf(ok);
    if (!best) continue;
    const front = ok.filter(r => r.pareto).sort((a, b) => a.ms - b.ms);
    const cell = el("td");
    front.forEach((r, k) => { if (k) cell.append("; "); cell.append(rowLink(r, rowSummary(r))); });
    table.append(el("tr", {}, el("td", {}, el("a", {href: "#" + sceneId(sc.name), text: sc.name})),
                    el("td", {}, rowLink(best, rowSummary(best))), cell));
  }
  document.getElementById("best-per-scene").append(table);
}

function buildBestPerFamily() {
  const base = scenes.filter(s => !s.base);
  const head = el("tr", {}, el("th", {text: "family"}));
  for (const sc of base) head.append(el("th", {text: sc.name}));
  const table = el("table", {}, head);
  for (const f of families) {
    const tr = el("tr", {}, el("td", {}, el("a", {href: "#family-" + f, text: f, title: familyTitle(f)})));
    for (const sc of base) {
      const best = bestOf(okRows(sc.name).filter(r => r.family === f));
      tr.append(best ? el("td", {class: "num"}, rowLink(best, fmt(best.rmse, 4)), el("br"), best.technique)
                     : el("td", {text: "-"}));
    }
    table.append(tr);
  }
  document.getElementById("best-per-family").append(table);
}

// Per family, per technique and scene: its default row and its best row, each a link to the viewer.
function buildFamilies() {
  const section = document.getElementById("families");
  for (const f of families) {
    const techs = [...new Set(rows.filter(r => r.family === f).map(r => r.technique))];
    const table = el("table", {}, el("tr", {html: "<th>technique</th><th>scene</th><th>default</th><th>best setting</th>"}));
    for (const t of techs)
      for (const sc of scenes) {
        const same = okRows(sc.name).filter(r => r.technique === t);
        if (!same.length) continue;
        const def = same.find(r => r.def), best = bestOf(same);
        table.append(el("tr", {}, el("td", {text: t}), el("td", {text: sc.name}),
                        el("td", {}, def ? rowLink(def, `${fmt(def.rmse, 4)}, ${fmt(def.ms, 2)} ms`) : "-"),
                        el("td", {}, rowLink(best, `${best.settings}: ${fmt(best.rmse, 4)}, ${fmt(best.ms, 2)} ms`))));
      }
    section.append(el("details", {id: "family-" + f},
                      el("summary", {html: `<span class="swatch" style="background:${familyColor[f]}"></span>` +
                                           `<b>${f}</b>: ${familyTitle(f)} (${techs.join(", ")})`}), table));
  }
}

function buildScenes() {
  const section = document.getElementById("scenes");
  for (const sc of scenes) {
    const ok = okRows(sc.name);
    const front = ok.filter(r => r.pareto).sort((a, b) => a.ms - b.ms);
    const svg = plot({
      xlog: true, xlabel: "GPU + CPU ms per frame (log)", ylabel: "RMSE",
      points: ok.map(r => ({x: r.ms, y: r.rmse, color: familyColor[r.family], row: r.index, ring: r.def,
                            big: r.pareto, tip: rowTip(r)})),
      lines: [{points: front.map(r => [r.ms, r.rmse]), color: "#000", dash: true, step: true}]});
    svg.dataset.scene = sc.name;
    const box = el("div", {class: "scene", id: sceneId(sc.name)}, el("h3", {text: sc.name}),
                   el("p", {text: `${sc.description} (${sc.triangles} triangles; ${sc.light}; reference ` +
                                  `${sc.ref_samples > 1 ? sc.ref_samples + " rays per pixel" : "one exact ray per pixel"})`}),
                   svg, legend([...new Set(ok.map(r => r.family))]));
    const failed = rows.filter(r => r.scene === sc.name && r.failed);
    if (failed.length)
      box.append(el("p", {text: "failed: " + failed.map(r => `${rowLabel(r)}: ${r.failed}`).join("; ")}));
    section.append(box);
  }
}

function legend(fams) {
  const d = el("div", {class: "legend"});
  for (const f of fams)
    d.append(el("span", {html: `<span class="swatch" style="background:${familyColor[f]}"></span>${f}`}));
  return d;
}

// Each soft technique's best RMSE against the light's size, per scene that has light-size variants.
function buildLightSize() {
  const section = document.getElementById("light-size");
  const groups = scenes.filter(s => !s.base && scenes.some(v => v.base === s.name));
  if (!groups.length) {
    section.append(el("p", {text: "No light-size variants in this run (--light-sizes; --quick runs none)."}));
    return;
  }
  for (const base of groups) {
    const group = [base, ...scenes.filter(v => v.base === base.name)].sort((a, b) => a.light_size - b.light_size);
    const techs = [...new Set(rows.filter(r => r.scene.startsWith(base.name + "@light=")).map(r => r.technique))];
    const points = [], lines = [];
    techs.forEach((t, k) => {
      const color = PALETTE[k % PALETTE.length], line = [];
      for (const sc of group) {
        const best = bestOf(okRows(sc.name).filter(r => r.technique === t));
        if (!best) continue;
        line.push([sc.light_size, best.rmse]);
        points.push({x: sc.light_size, y: best.rmse, color, row: best.index,
                     tip: `${esc(sc.light)}<br>` + rowTip(best)});
      }
      lines.push({points: line, color});
    });
    const svg = plot({xlabel: "light size (edge or radius)", ylabel: "best RMSE", points, lines});
    const key = el("div", {class: "legend"});
    techs.forEach((t, k) => key.append(el("span", {html: `<span class="swatch" style="background:${PALETTE[k % PALETTE.length]}"></span>${t}`})));
    section.append(el("div", {class: "scene"}, el("h3", {text: base.name}), svg, key));
  }
}

// Per scene with temporal rows: each (row, path) at (RMSE, temporal RMS).
function buildFlicker() {
  const section = document.getElementById("flicker");
  let any = false;
  for (const sc of scenes) {
    const points = [];
    for (const r of okRows(sc.name))
      for (const t of r.temporal || [])
        points.push({x: r.rmse, y: t.rms, color: familyColor[r.family], row: r.index,
                     tip: rowTip(r) + `<br>${t.path}: temporal RMS ${fmt(t.rms, 4)}, flips ${pct(t.flips)}`});
    if (!points.length) continue;
    any = true;
    section.append(el("div", {class: "scene"}, el("h3", {text: sc.name}),
                      plot({xlabel: "RMSE (still frame)", ylabel: "temporal RMS", points})));
  }
  if (!any) section.append(el("p", {text: "No temporal rows in this run (--temporal off)."}));
}

function buildLightSweep() {
  const section = document.getElementById("light-sweep");
  const sweep = REPORT.light_sweep || [];
  if (!sweep.length) {
    section.append(el("p", {text: "No light sweep in this run (--light-sweep off)."}));
    return;
  }
  section.append(el("p", {text: "The hard shadow-map techniques at their defaults under random lights (a third " +
    "grazing), the maxima over the lights: acne (pixels wrongly dark beyond the filter), contact gaps, umbra leaks."}));
  const table = el("table", {}, el("tr", {html: "<th>scene</th><th>technique</th><th>light</th><th>lights (grazing)</th>" +
    "<th>acne max</th><th>lights with acne</th><th>gap max, texels</th><th>leak max</th><th>lights with leak</th><th>s</th>"}));
  for (const s of sweep)
    table.append(el("tr", {html: `<td>${esc(s.scene)}</td><td>${esc(s.technique + " " + s.settings)}</td><td>${esc(s.light)}</td>` +
      `<td class="num">${s.lights} (${s.grazing_lights})</td><td class="num">${pct3(s.acne_fraction_max)}</td>` +
      `<td class="num">${s.lights_with_acne}</td><td class="num">${fmt(s.gap_texels_max, 2)}</td>` +
      `<td class="num">${pct3(s.leak_fraction_max)}</td><td class="num">${s.lights_with_leak}</td>` +
      `<td class="num">${fmt(s.seconds, 1)}</td>`}));
  section.append(table);
}

// A link to #family-x or #scene-y opens its <details> and scrolls there.
function openHashTarget() {
  const target = location.hash && document.getElementById(decodeURIComponent(location.hash.slice(1)));
  if (!target) return;
  if (target.tagName === "DETAILS") target.open = true;
  target.scrollIntoView();
}

buildRunInfo();
buildFilters();
buildBestPerScene();
buildBestPerFamily();
buildFamilies();
buildScenes();
buildLightSize();
buildFlicker();
buildLightSweep();
buildViewer();
applyFilters();
window.addEventListener("hashchange", openHashTarget);
openHashTarget();
