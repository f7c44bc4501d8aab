/* report_html.c — the page of `rtgi bench` (report_html.h). The page is
 * this file's two strings (the head with its markup and styles, the script
 * that draws) around the data: the bench JSON and the images. */
#include "io/report_html.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/log.h"
#include "io/report_temporal.h"
#include "base/util.h"

static const char k_head[] =
    "<!doctype html>\n"
    "<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
    "<title>rtgi bench</title>\n"
    "<script>\n"
    "/* Errors first: the tests read the title back. */\n"
    "window.benchErrors = [];\n"
    "window.onerror = function (msg, src, line) {\n"
    "  window.benchErrors.push(msg + ' (line ' + line + ')');\n"
    "  document.title = 'error: ' + msg;\n"
    "};\n"
    "(function () {\n"
    "  var ce = console.error;\n"
    "  console.error = function () {\n"
    "    window.benchErrors.push(Array.prototype.join.call(arguments, ' '));\n"
    "    document.title = 'error: console';\n"
    "    ce.apply(console, arguments);\n"
    "  };\n"
    "})();\n"
    "</script>\n"
    "<style>\n"
    "body { font: 14px/1.4 system-ui, sans-serif; margin: 16px 24px; color: #222; background: #fafafa; }\n"
    "h1 { font-size: 20px; margin: 0 0 4px; } h2 { font-size: 16px; margin: 20px 0 6px; }\n"
    ".meta { color: #555; font-size: 12px; } .meta b { color: #222; }\n"
    ".grid { display: flex; flex-wrap: wrap; gap: 10px; }\n"
    ".card { background: #fff; border: 1px solid #ddd; padding: 6px; border-radius: 4px; width: 340px; }\n"
    ".card .t { font-size: 12px; margin-bottom: 4px; height: 32px; overflow: hidden; }\n"
    ".card canvas { width: 164px; cursor: zoom-in; background: #000; }\n"
    "table { border-collapse: collapse; background: #fff; font-size: 12px; }\n"
    "td, th { border: 1px solid #ddd; padding: 3px 6px; text-align: right; } td:first-child, th:first-child { text-align: left; }\n"
    "tr.pareto td:first-child { font-weight: bold; }\n"
    "#modal { display: none; position: fixed; inset: 0; background: rgba(0,0,0,.85); z-index: 9; text-align: center; }\n"
    "#modal canvas { max-width: 95vw; max-height: 85vh; image-rendering: pixelated; margin-top: 3vh; }\n"
    "#modal div { color: #eee; margin-top: 6px; }\n"
    "svg text { font-size: 11px; fill: #333; } .ctl { margin: 6px 0; }\n"
    "</style></head><body>\n"
    "<h1>rtgi bench</h1>\n"
    "<div class=\"meta\" id=\"meta\"></div>\n"
    "<div id=\"status\" class=\"meta\">loading…</div>\n"
    "<h2>Metrics (emitters masked out)</h2>\n"
    "<table id=\"metrics\"></table>\n"
    "<h2>Time per pass</h2>\n"
    "<div class=\"ctl\">time <select id=\"timesrc\"><option value=\"gpu_ms\">GPU (timer queries)</option>\n"
    "<option value=\"wall_ms\">wall (glFinish around each pass)</option></select></div>\n"
    "<svg id=\"bars\"></svg>\n"
    "<h2>Quality versus cost</h2>\n"
    "<div class=\"ctl\">error <select id=\"ymetric\"><option value=\"flip\">FLIP</option><option value=\"relmse\">relMSE</option>\n"
    "<option value=\"rmse\">RMSE</option><option value=\"dssim\">1 − SSIM</option></select>\n"
    "cost <select id=\"xcost\"><option value=\"frame_ms\">ms per frame (wall)</option><option value=\"gpu_ms\">GPU ms</option></select>\n"
    "— the line joins the Pareto front (nothing both faster and better)</div>\n"
    "<svg id=\"scatter\" width=\"760\" height=\"440\"></svg>\n"
    "<h2>Images</h2>\n"
    "<div class=\"ctl\">exposure <input type=\"range\" id=\"exp\" min=\"-6\" max=\"6\" step=\"0.25\" value=\"0\">\n"
    "<span id=\"expv\"></span> (0 = the reference's log-average luminance at 18% grey, its 90th percentile at most at white) · FLIP\n"
    "<canvas id=\"cbar\" width=\"256\" height=\"12\" style=\"vertical-align: middle; border: 1px solid #999\"></canvas>\n"
    "<span style=\"font-size: 11px\">0 … 0.5 … 1</span> · click an image to enlarge</div>\n"
    "<div class=\"grid\" id=\"cards\"></div>\n"
    "<div id=\"modal\"><canvas id=\"big\"></canvas><div id=\"bigt\"></div></div>\n"
    "\n";

static const char k_app[] =
    "(function () {\n"
    "  'use strict';\n"
    "  var B = BENCH, T = B.techniques;\n"
    "  var NSHADOW = T.map(function (t) { return t.shadow; }).filter(function (s, i, a) { return a.indexOf(s) === i; }).length;\n"
    "  function el(tag, attrs, text) {\n"
    "    var e = document.createElementNS(tag === 'svg' || SVGT[tag] ? 'http://www.w3.org/2000/svg' : 'http://www.w3.org/1999/xhtml', tag);\n"
    "    for (var k in attrs || {}) e.setAttribute(k, attrs[k]);\n"
    "    if (text !== undefined) e.textContent = text;\n"
    "    return e;\n"
    "  }\n"
    "  var SVGT = { rect: 1, circle: 1, line: 1, polyline: 1, text: 1, title: 1, g: 1 };\n"
    "  function fmt(v, d) { return v === null || v === undefined ? '—' : (Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(2) : v.toFixed(d)); }\n"
    "\n"
    "  /* Meta. */\n"
    "  var meta = document.getElementById('meta');\n"
    "  meta.innerHTML = '';\n"
    "  [['scene', B.scene], ['size', B.width + '×' + B.height + (B.ssaa > 1 ? ' (SSAA ' + B.ssaa + '×' + B.ssaa + ')' : '')], ['reference', B.reference.mode + ', ' + B.reference.spp + ' spp'],\n"
    "   ['commit', B.commit], ['date', B.date], ['device', B.device], ['GL renderer', B.gl_renderer],\n"
    "   ['frames', B.frames], ['FLIP/SSIM exposure', B.metric_exposure]].forEach(function (kv) {\n"
    "    meta.appendChild(el('b', {}, kv[0] + ': ')); meta.appendChild(document.createTextNode(kv[1] + '  · '));\n"
    "  });\n"
    "\n"
    "  /* Images: half-float radiance, tone-mapped here. */\n"
    "  var H2F = new Float32Array(65536);\n"
    "  for (var h = 0; h < 65536; h++) {\n"
    "    var s = h & 0x8000 ? -1 : 1, e = (h >> 10) & 31, f = h & 1023;\n"
    "    H2F[h] = e === 0 ? s * f * Math.pow(2, -24) : e === 31 ? 0 : s * (1 + f / 1024) * Math.pow(2, e - 15);\n"
    "  }\n"
    "  function bytes(b64) { var bin = atob(b64), u = new Uint8Array(bin.length); for (var i = 0; i < bin.length; i++) u[i] = bin.charCodeAt(i); return u; }\n"
    "  var SRGB = new Uint8Array(4097);\n"
    "  for (var i = 0; i <= 4096; i++) { var c = i / 4096; SRGB[i] = Math.round(255 * (c <= 0.0031308 ? 12.92 * c : 1.055 * Math.pow(c, 1 / 2.4) - 0.055)); }\n"
    "  var MAGMA = [[0, 0, 4], [28, 16, 68], [79, 18, 123], [129, 37, 129], [181, 54, 122], [229, 80, 100], [251, 135, 97], [254, 194, 135], [252, 253, 191]];\n"
    "  function magma(v) {\n"
    "    var x = Math.max(0, Math.min(1, v)) * 8, k = Math.min(7, Math.floor(x)), t = x - k;\n"
    "    return [0, 1, 2].map(function (c) { return Math.round(MAGMA[k][c] * (1 - t) + MAGMA[k + 1][c] * t); });\n"
    "  }\n"
    "  var imgs = {};\n"
    "  Object.keys(IMAGES).forEach(function (id) {\n"
    "    var I = IMAGES[id], u = bytes(I.hdr);\n"
    "    var hdr = new Float32Array(I.w * I.h * 3), h16 = new Uint16Array(u.buffer, u.byteOffset, I.w * I.h * 3);\n"
    "    for (var i = 0; i < hdr.length; i++) hdr[i] = H2F[h16[i]];\n"
    "    imgs[id] = { w: I.w, h: I.h, hdr: hdr, flip: I.flip ? bytes(I.flip) : null };\n"
    "  });\n"
    "  function tonemap(cv, im, exposure) {\n"
    "    var ctx = cv.getContext('2d'), d = ctx.createImageData(im.w, im.h);\n"
    "    for (var p = 0, q = 0; p < im.w * im.h; p++) {\n"
    "      for (var c = 0; c < 3; c++) {\n"
    "        var v = im.hdr[3 * p + c] * exposure;\n"
    "        d.data[q++] = SRGB[v <= 0 ? 0 : v >= 1 ? 4096 : Math.round(v * 4096)];\n"
    "      }\n"
    "      d.data[q++] = 255;\n"
    "    }\n"
    "    ctx.putImageData(d, 0, 0);\n"
    "  }\n"
    "  function heat(cv, im) {\n"
    "    var ctx = cv.getContext('2d'), d = ctx.createImageData(im.w, im.h);\n"
    "    for (var p = 0; p < im.w * im.h; p++) {\n"
    "      var m = magma(im.flip[p] / 255);\n"
    "      d.data[4 * p] = m[0]; d.data[4 * p + 1] = m[1]; d.data[4 * p + 2] = m[2]; d.data[4 * p + 3] = 255;\n"
    "    }\n"
    "    ctx.putImageData(d, 0, 0);\n"
    "  }\n"
    "  var cb = document.getElementById('cbar').getContext('2d');\n"
    "  for (var x = 0; x < 256; x++) { var m = magma(x / 255); cb.fillStyle = 'rgb(' + m + ')'; cb.fillRect(x, 0, 1, 12); }\n"
    "\n"
    "  var cards = document.getElementById('cards'), canvases = [];\n"
    "  var modal = document.getElementById('modal'), big = document.getElementById('big');\n"
    "  function enlarge(cv, title) {\n"
    "    big.width = cv.width; big.height = cv.height;\n"
    "    big.getContext('2d').drawImage(cv, 0, 0);\n"
    "    document.getElementById('bigt').textContent = title + ' — click to close';\n"
    "    modal.style.display = 'block';\n"
    "  }\n"
    "  modal.onclick = function () { modal.style.display = 'none'; };\n"
    "  var list = [{ id: 'reference', label: 'reference (' + B.reference.mode + ', ' + B.reference.spp + ' spp)' }].concat(T);\n"
    "  list.forEach(function (t) {\n"
    "    var im = imgs[t.id]; if (!im) return;\n"
    "    var card = el('div', { class: 'card' });\n"
    "    var title = t.label + (t.metrics ? ' — FLIP ' + fmt(t.metrics.flip, 4) + ', ' + fmt(t.frame_ms, 1) + ' ms' : '');\n"
    "    card.appendChild(el('div', { class: 't' }, title));\n"
    "    var cv = el('canvas', { width: im.w, height: im.h, title: 'radiance' });\n"
    "    cv.onclick = function () { enlarge(cv, t.label); };\n"
    "    card.appendChild(cv); canvases.push([cv, im]);\n"
    "    if (im.flip) {\n"
    "      var hv = el('canvas', { width: im.w, height: im.h, title: 'FLIP' });\n"
    "      hv.style.marginLeft = '4px';\n"
    "      heat(hv, im);\n"
    "      hv.onclick = function () { enlarge(hv, t.label + ' (FLIP)'); };\n"
    "      card.appendChild(hv);\n"
    "    }\n"
    "    cards.appendChild(card);\n"
    "  });\n"
    "  var expInput = document.getElementById('exp');\n"
    "  function expose() {\n"
    "    var e = B.display_exposure * Math.pow(2, +expInput.value);\n"
    "    document.getElementById('expv').textContent = (+expInput.value >= 0 ? '+' : '') + expInput.value + ' stops (×' + e.toPrecision(3) + ')';\n"
    "    canvases.forEach(function (ci) { tonemap(ci[0], ci[1], e); });\n"
    "  }\n"
    "  expInput.oninput = expose;\n"
    "  expose();\n"
    "  /* For the sections other scripts add (report_temporal.c). */\n"
    "  window.rtgiBench = { imgs: imgs, tonemap: tonemap, el: el, fmt: fmt,\n"
    "    exposure: function () { return B.display_exposure * Math.pow(2, +expInput.value); } };\n"
    "\n"
    "  /* Pareto front of (cost, error): nothing both cheaper and better. */\n"
    "  function yval(t, key) { var m = t.metrics; return key === 'dssim' ? (m.ssim === null ? null : 1 - m.ssim) : m[key]; }\n"
    "  function pareto(xkey, ykey) {\n"
    "    var pts = T.filter(function (t) { return t[xkey] !== null && yval(t, ykey) !== null; })\n"
    "      .sort(function (a, b) { return a[xkey] - b[xkey] || yval(a, ykey) - yval(b, ykey); });\n"
    "    var front = [], best = Infinity;\n"
    "    pts.forEach(function (t) { var y = yval(t, ykey); if (y < best) { front.push(t); best = y; } });\n"
    "    return front;\n"
    "  }\n"
    "\n"
    "  /* Metrics table. */\n"
    "  function table() {\n"
    "    var tb = document.getElementById('metrics'), front = pareto('frame_ms', 'flip');\n"
    "    tb.innerHTML = '';\n"
    "    var hr = el('tr');\n"
    "    ['technique', 'ms/frame', 'GPU ms', 'GI MiB', 'GPU MiB (all)', 'RMSE', 'relMSE', 'FLIP', 'SSIM', 'mean ÷ ref', 'Pareto (FLIP, ms)'].forEach(function (h) { hr.appendChild(el('th', {}, h)); });\n"
    "    tb.appendChild(hr);\n"
    "    T.forEach(function (t) {\n"
    "      var on = front.indexOf(t) >= 0, tr = el('tr', on ? { class: 'pareto' } : {});\n"
    "      [t.label, fmt(t.frame_ms, 2), fmt(t.gpu_ms, 2), fmt(t.stats.gi_memory_mib, 3), fmt(t.stats.gpu_memory_mib, 1), fmt(t.metrics.rmse, 5), fmt(t.metrics.relmse, 5), fmt(t.metrics.flip, 4),\n"
    "       fmt(t.metrics.ssim, 4), fmt(t.metrics.mean_ratio, 3), on ? '✓' : ''].forEach(function (v) { tr.appendChild(el('td', {}, v)); });\n"
    "      tb.appendChild(tr);\n"
    "    });\n"
    "  }\n"
    "\n"
    "  /* Per-pass stacked bars. */\n"
    "  /* Distinct hues by the golden angle, alternating lightness. */\n"
    "  function PALC(i) { return 'hsl(' + Math.round(i * 137.508) % 360 + ',' + (i % 2 ? 55 : 70) + '%,' + (i % 3 === 2 ? 38 : 52) + '%)'; }\n"
    "  var passColor = {}, npass = 0;\n"
    "  T.forEach(function (t) { t.passes.forEach(function (p) { if (!(p.name in passColor)) passColor[p.name] = PALC(npass++); }); });\n"
    "  function bars() {\n"
    "    var key = document.getElementById('timesrc').value, svg = document.getElementById('bars');\n"
    "    while (svg.firstChild) svg.removeChild(svg.firstChild);\n"
    "    var left = 280, W = 480, rowh = 20, max = 0;\n"
    "    T.forEach(function (t) { var s = 0; t.passes.forEach(function (p) { s += p[key] || 0; }); max = Math.max(max, s); });\n"
    "    var H = T.length * rowh + 60;\n"
    "    svg.setAttribute('width', left + W + 90); svg.setAttribute('height', H);\n"
    "    T.forEach(function (t, i) {\n"
    "      var y = 10 + i * rowh, x = left, s = 0;\n"
    "      svg.appendChild(el('text', { x: 0, y: y + 13 }, t.label));\n"
    "      t.passes.forEach(function (p) {\n"
    "        var v = p[key] || 0, w = max > 0 ? v / max * W : 0;\n"
    "        var r = el('rect', { x: x, y: y, width: Math.max(w, 0), height: rowh - 4, fill: passColor[p.name] });\n"
    "        r.appendChild(el('title', {}, p.name + ': ' + fmt(v, 2) + ' ms'));\n"
    "        svg.appendChild(r); x += w; s += v;\n"
    "      });\n"
    "      svg.appendChild(el('text', { x: x + 4, y: y + 13 }, fmt(s, 1) + ' ms'));\n"
    "    });\n"
    "    var lx = 0, ly = T.length * rowh + 30;\n"
    "    Object.keys(passColor).forEach(function (n) {\n"
    "      svg.appendChild(el('rect', { x: lx, y: ly, width: 10, height: 10, fill: passColor[n] }));\n"
    "      svg.appendChild(el('text', { x: lx + 13, y: ly + 9 }, n));\n"
    "      lx += 14 + 7 * n.length + 12;\n"
    "      if (lx > left + W - 60) { lx = 0; ly += 14; svg.setAttribute('height', ly + 20); }\n"
    "    });\n"
    "  }\n"
    "\n"
    "  /* Quality versus cost. */\n"
    "  function scatter() {\n"
    "    var xkey = document.getElementById('xcost').value, ykey = document.getElementById('ymetric').value;\n"
    "    var svg = document.getElementById('scatter');\n"
    "    while (svg.firstChild) svg.removeChild(svg.firstChild);\n"
    "    var L = 70, R = 660, Tp = 20, Bt = 390;\n"
    "    var pts = T.filter(function (t) { return t[xkey] !== null && t[xkey] > 0 && yval(t, ykey) !== null; });\n"
    "    var xs = pts.map(function (t) { return t[xkey]; }), ys = pts.map(function (t) { return yval(t, ykey); });\n"
    "    var x0 = Math.min.apply(null, xs.concat([1e9])), x1 = Math.max.apply(null, xs.concat([1e-9]));\n"
    "    var logx = x1 / x0 > 20;\n"
    "    function sx(v) {\n"
    "      if (x1 <= x0) return (L + R) / 2;\n"
    "      return logx ? L + (Math.log(v / x0) / Math.log(x1 / x0)) * (R - L) : L + (v - x0 * 0.9) / (x1 * 1.05 - x0 * 0.9) * (R - L);\n"
    "    }\n"
    "    var y1 = Math.max.apply(null, ys.concat([1e-12])) * 1.1;\n"
    "    function sy(v) { return Bt - v / y1 * (Bt - Tp); }\n"
    "    svg.appendChild(el('line', { x1: L, y1: Bt, x2: R, y2: Bt, stroke: '#333' }));\n"
    "    svg.appendChild(el('line', { x1: L, y1: Tp, x2: L, y2: Bt, stroke: '#333' }));\n"
    "    for (var k = 0; k <= 4; k++) {\n"
    "      var yv = y1 * k / 4;\n"
    "      svg.appendChild(el('text', { x: 4, y: sy(yv) + 4 }, fmt(yv, 4)));\n"
    "      svg.appendChild(el('line', { x1: L - 3, y1: sy(yv), x2: L, y2: sy(yv), stroke: '#333' }));\n"
    "    }\n"
    "    var ticks = logx ? [] : [x0, (x0 + x1) / 2, x1];\n"
    "    if (logx) for (var d = Math.pow(10, Math.floor(Math.log10(x0))); d <= x1 * 1.001; d *= 10) [1, 2, 5].forEach(function (m) { if (d * m >= x0 && d * m <= x1) ticks.push(d * m); });\n"
    "    ticks.forEach(function (v) {\n"
    "      svg.appendChild(el('line', { x1: sx(v), y1: Bt, x2: sx(v), y2: Bt + 4, stroke: '#333' }));\n"
    "      svg.appendChild(el('text', { x: sx(v) - 10, y: Bt + 16 }, fmt(v, 1)));\n"
    "    });\n"
    "    svg.appendChild(el('text', { x: (L + R) / 2 - 60, y: Bt + 36 }, (xkey === 'gpu_ms' ? 'GPU ms' : 'ms per frame') + (logx ? ' (log scale)' : '')));\n"
    "    svg.appendChild(el('text', { x: 4, y: 12 }, document.getElementById('ymetric').selectedOptions[0].text + ' (lower is better)'));\n"
    "    var front = pareto(xkey, ykey);\n"
    "    svg.appendChild(el('polyline', { points: front.map(function (t) { return sx(t[xkey]) + ',' + sy(yval(t, ykey)); }).join(' '),\n"
    "      fill: 'none', stroke: '#e15759', 'stroke-width': 2, 'stroke-dasharray': '5,3', class: 'front' }));\n"
    "    /* Points first, then their labels, each at the first of a few places\n"
    "     * around its point that overlaps no point or label placed before (else\n"
    "     * where it overlaps least, with a leader line to its point); the hover\n"
    "     * title names every point in full. */\n"
    "    var boxes = [];\n"
    "    function overlap(a, b) { return Math.max(0, Math.min(a.x1, b.x1) - Math.max(a.x0, b.x0)) * Math.max(0, Math.min(a.y1, b.y1) - Math.max(a.y0, b.y0)); }\n"
    "    pts.forEach(function (t) {\n"
    "      var on = front.indexOf(t) >= 0, px = sx(t[xkey]), py = sy(yval(t, ykey)), r = on ? 6 : 4.5;\n"
    "      var c = el('circle', { cx: px, cy: py, r: r, fill: on ? '#e15759' : '#4e79a7', class: 'pt' });\n"
    "      c.appendChild(el('title', {}, t.label + ': ' + fmt(t[xkey], 2) + ' ms, ' + fmt(yval(t, ykey), 5)));\n"
    "      svg.appendChild(c);\n"
    "      boxes.push({ x0: px - r, y0: py - r, x1: px + r, y1: py + r });\n"
    "    });\n"
    "    var overlaps = 0, SW = +svg.getAttribute('width');\n"
    "    pts.forEach(function (t) {\n"
    "      var px = sx(t[xkey]), py = sy(yval(t, ykey));\n"
    "      var tx = el('text', { x: 0, y: 0, class: 'lbl' }, t.gi + (t.overrides ? '*' : '') + (NSHADOW > 1 ? '/' + t.shadow : ''));\n"
    "      svg.appendChild(tx);\n"
    "      var bb = tx.getBBox(), w = bb.width, h = bb.height, best = null, bestOv = Infinity;\n"
    "      [[8, -6], [8, 4 + h], [-8 - w, -6], [-8 - w, 4 + h], [-w / 2, -9], [-w / 2, 10 + h],\n"
    "       [8, -6 - h], [8, 4 + 2 * h], [-8 - w, -6 - h], [-8 - w, 4 + 2 * h], [-w / 2, -9 - h], [-w / 2, 10 + 2 * h],\n"
    "       [14, -6 - 2 * h], [14, 4 + 3 * h], [-14 - w, -6 - 2 * h], [-14 - w, 4 + 3 * h]].forEach(function (d) {\n"
    "        var x = px + d[0], y = py + d[1];\n"
    "        var b = { x0: x + bb.x, y0: y + bb.y, x1: x + bb.x + w, y1: y + bb.y + h };\n"
    "        var ov = b.x0 < 0 || b.x1 > SW || b.y0 < 0 || b.y1 > Bt ? 1e6 : 0;\n"
    "        boxes.forEach(function (o) { ov += overlap(b, o); });\n"
    "        if (ov < bestOv) { bestOv = ov; best = { x: x, y: y, b: b }; }\n"
    "      });\n"
    "      tx.setAttribute('x', best.x); tx.setAttribute('y', best.y);\n"
    "      if (bestOv > 0) overlaps++;\n"
    "      if (Math.abs(best.y - py) > 4 + 2 * h || Math.abs(best.x - px) > 20 + w)\n"
    "        svg.insertBefore(el('line', { x1: px, y1: py, x2: Math.max(best.b.x0, Math.min(px, best.b.x1)), y2: Math.max(best.b.y0, Math.min(py, best.b.y1)), stroke: '#999' }), svg.firstChild);\n"
    "      boxes.push(best.b);\n"
    "    });\n"
    "    svg.setAttribute('data-label-overlaps', overlaps);\n"
    "    return pts.length;\n"
    "  }\n"
    "  document.getElementById('timesrc').onchange = bars;\n"
    "  document.getElementById('ymetric').onchange = scatter;\n"
    "  document.getElementById('xcost').onchange = scatter;\n"
    "  table();\n"
    "  bars();\n"
    "  var npts = scatter();\n"
    "  var st = document.getElementById('status');\n"
    "  if (window.benchErrors.length) {\n"
    "    st.textContent = 'errors: ' + window.benchErrors.join('; ');\n"
    "  } else {\n"
    "    st.textContent = 'ok: ' + T.length + ' techniques, ' + npts + ' points, ' + document.getElementById('scatter').getAttribute('data-label-overlaps') + ' overlapping labels';\n"
    "    document.title = 'ok:' + document.querySelectorAll('#scatter circle.pt').length;\n"
    "  }\n"
    "})();\n"
    "\n";

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

double report_display_exposure(const ImageF *ref, const uint8_t *mask)
{
    size_t np = (size_t)ref->width * ref->height, n = 0;
    float *l = malloc((np ? np : 1) * sizeof(float));
    if (!l)
        return 0;
    double log_sum = 0;
    for (size_t i = 0; i < np; i++) {
        if (mask && !mask[i])
            continue;
        const float *c = ref->rgb + 3 * i;
        float y = luminance(c);
        y = isfinite(y) && y > 0.f ? y : 0.f;
        l[n++] = y;
        log_sum += log(1e-4 + y);
    }
    double e = 0;
    if (n > 0) {
        qsort(l, n, sizeof(float), cmp_float);
        double p90 = l[(size_t)(0.9 * (double)(n - 1))], peak = l[n - 1];
        double key = 0.18 / fmax(exp(log_sum / (double)n) - 1e-4, 1e-12);
        e = p90 > 0 ? fmin(key, 1.0 / p90) : peak > 0 ? 1.0 / peak : 0;
    }
    free(l);
    return e;
}

/* IEEE half from float, round to nearest even; beyond 65504 saturates. */
static uint16_t half_from_float(float f)
{
    uint32_t x;
    memcpy(&x, &f, 4);
    uint32_t sign = (x >> 16) & 0x8000u, a = x & 0x7fffffffu;
    if (a >= 0x477fe000u) /* ≥ 65520 (rounds to inf) or NaN: saturate */
        return (uint16_t)(sign | 0x7bffu);
    if (a < 0x38800000u) { /* subnormal half (or zero) */
        if (a < 0x33000000u)
            return (uint16_t)sign;
        uint32_t m = (a & 0x7fffffu) | 0x800000u;
        int shift = 126 - (int)(a >> 23); /* 14..24 */
        /* value = m · 2^(e-150); half subnormal unit 2^-24: h = m · 2^(e-126) */
        uint32_t rem = m & ((1u << shift) - 1), halfway = 1u << (shift - 1);
        uint32_t h = m >> shift;
        if (rem > halfway || (rem == halfway && (h & 1)))
            h++;
        return (uint16_t)(sign | h);
    }
    uint32_t h = ((a - 0x38000000u) >> 13), rem = a & 0x1fffu;
    if (rem > 0x1000u || (rem == 0x1000u && (h & 1)))
        h++;
    return (uint16_t)(sign | h);
}

static void put_base64(FILE *f, const uint8_t *p, size_t n)
{
    static const char tab[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)p[i] << 16 | (i + 1 < n ? (uint32_t)p[i + 1] << 8 : 0) | (i + 2 < n ? p[i + 2] : 0);
        fputc(tab[v >> 18 & 63], f);
        fputc(tab[v >> 12 & 63], f);
        fputc(i + 1 < n ? tab[v >> 6 & 63] : '=', f);
        fputc(i + 2 < n ? tab[v & 63] : '=', f);
    }
}

/* The JSON inside a <script>, with every '<' written as \u003c (JSON has
 * '<' only inside strings, where the escape means the same): "</script"
 * would end the block, and "<!--" followed by "<script" would make the
 * parser skip the block's "</script>", leaving the page one broken script. */
static void put_script_json(FILE *f, const char *json)
{
    for (const char *c = json; *c; c++) {
        if (*c == '<')
            fputs("\\u003c", f);
        else
            fputc(*c, f);
    }
}

bool report_html_write(const char *path, const cJSON *bench, const ReportImage *imgs, int n)
{
    char *json = cJSON_PrintUnformatted(bench);
    if (!json) {
        log_error("bench", "%s: cannot format the bench JSON (out of memory)", path);
        return false;
    }
    AtomicFile af;
    if (!util_atomic_open(&af, "bench", path)) {
        free(json);
        return false;
    }
    FILE *f = af.f;
    fputs(k_head, f);
    fputs("<script>\nconst BENCH = ", f);
    put_script_json(f, json);
    free(json);
    fputs(";\nconst IMAGES = {\n", f);
    bool ok = true;
    for (int i = 0; i < n && ok; i++) {
        const ImageF *im = imgs[i].img;
        size_t np = (size_t)im->width * im->height;
        uint16_t *h = malloc(np * 3 * sizeof(uint16_t));
        uint8_t *q = imgs[i].flip ? malloc(np) : NULL;
        if (!h || (imgs[i].flip && !q)) {
            log_error("bench", "%s: cannot allocate the page's copy of a %dx%d image", path, im->width, im->height);
            free(h);
            free(q);
            ok = false;
            break;
        }
        for (size_t k = 0; k < np * 3; k++)
            h[k] = half_from_float(im->rgb[k] > 0.f ? im->rgb[k] : 0.f);
        fprintf(f, "\"%s\": {\"w\": %d, \"h\": %d, \"hdr\": \"", imgs[i].id, im->width, im->height);
        put_base64(f, (const uint8_t *)h, np * 3 * sizeof(uint16_t)); /* little-endian, as the page reads it */
        fputs("\", \"flip\": ", f);
        if (q) {
            for (size_t k = 0; k < np; k++) {
                float v = imgs[i].flip[k];
                q[k] = (uint8_t)(isfinite(v) ? lrintf(255.f * (v < 0.f ? 0.f : v > 1.f ? 1.f : v)) : 0);
            }
            fputc('"', f);
            put_base64(f, q, np);
            fputc('"', f);
        } else {
            fputs("null", f);
        }
        fputs(i + 1 < n ? "},\n" : "}\n", f);
        free(h);
        free(q);
    }
    fputs("};\n</script>\n<script>\n", f);
    fputs(k_app, f);
    fputs("</script>\n<script>\n", f);
    fputs(report_temporal_script, f); /* bench --animate's section; nothing without it */
    fputs("</script>\n</body></html>\n", f);
    if (!ok) {
        util_atomic_abort(&af);
        return false;
    }
    return util_atomic_commit(&af, "bench");
}
