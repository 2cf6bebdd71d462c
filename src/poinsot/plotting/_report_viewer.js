// poinsot report viewer: a 3-D scene on a 2-D canvas and SVG time-series charts,
// driven by one animation clock. No library, no network. The page holds the data as
// JSON (#poinsot-data) with arrays as base64 little-endian float32 / uint32.
//
// Scene: space axes (z up), orthographic camera orbiting the box centre (drag to turn,
// wheel to zoom, double-click to reset). Triangles, segments and markers are sorted
// back to front (painter's algorithm); faces are shaded by |n . light|.
// Conventions: quaternions scalar first (w, x, y, z), v_space = q v_body q~.
"use strict";
(function () {
  const SVGNS = "http://www.w3.org/2000/svg";

  function bytes(s) {
    const b = atob(s), u = new Uint8Array(b.length);
    for (let i = 0; i < b.length; i++) u[i] = b.charCodeAt(i);
    return u;
  }
  function f32(s) { return s == null ? null : new Float32Array(bytes(s).buffer); }
  function u32(s) { return s == null ? null : new Uint32Array(bytes(s).buffer); }

  // out[k..k+2] = R(q) (x, y, z), q = (w, x, y, z) at q[o..o+3]
  function qrot(q, o, x, y, z, out, k) {
    const w = q[o], qx = q[o + 1], qy = q[o + 2], qz = q[o + 3];
    const tx = 2 * (qy * z - qz * y), ty = 2 * (qz * x - qx * z), tz = 2 * (qx * y - qy * x);
    out[k] = x + w * tx + (qy * tz - qz * ty);
    out[k + 1] = y + w * ty + (qz * tx - qx * tz);
    out[k + 2] = z + w * tz + (qx * ty - qy * tx);
  }

  // "nice" ticks covering [lo, hi]
  function ticks(lo, hi, n) {
    const span = hi - lo;
    if (!(span > 0) || !isFinite(span)) return {step: 1, v: [lo]};
    const raw = span / n, p = Math.pow(10, Math.floor(Math.log10(raw))), r = raw / p;
    const step = (r < 1.5 ? 1 : r < 3 ? 2 : r < 7 ? 5 : 10) * p;
    const v = [];
    for (let x = Math.ceil(lo / step - 1e-9) * step; x <= hi + step * 1e-9; x += step) {
      v.push(Math.abs(x) < step * 1e-9 ? 0 : x);
    }
    return {step, v};
  }
  function fmtTick(x, step, big) {
    if (x === 0) return "0";
    if (big >= 1e5 || big < 1e-3) {
      const d = Math.max(0, Math.floor(Math.log10(Math.abs(x)) + 1e-9) -
                         Math.floor(Math.log10(step) + 1e-9));
      return x.toExponential(Math.min(d, 6)).replace("e+", "e");
    }
    return x.toFixed(Math.max(0, Math.min(10, -Math.floor(Math.log10(step) + 1e-9))));
  }
  function fmtVal(x) {
    if (!isFinite(x)) return String(x);
    if (x === 0) return "0";
    const a = Math.abs(x);
    return (a >= 1e5 || a < 1e-3) ? x.toExponential(4).replace("e+", "e") : String(+x.toPrecision(5));
  }
  function rgb(hex) {
    return [1, 3, 5].map(i => parseInt(hex.slice(i, i + 2), 16));
  }
  function el(tag, attrs, parent, ns) {
    const e = ns ? document.createElementNS(ns, tag) : document.createElement(tag);
    for (const k in attrs || {}) e.setAttribute(k, attrs[k]);
    if (parent) parent.appendChild(e);
    return e;
  }

  // ------------------------------------------------------------------ the 3-D scene
  function Scene(root, S, q, qref, bp) {
    const legend = el("div", {class: "pv-legend", id: "poinsot-legend"}, root);
    const canvas = el("canvas", {id: "poinsot-scene", "aria-label": "3-D scene"}, root);
    el("p", {class: "pv-hint"}, root).textContent =
      "Drag to turn the view, wheel to zoom, double-click to reset. Click a legend item to " +
      "show or hide it.";
    const ctx = canvas.getContext("2d");
    const lo = S.lo, hi = S.hi, c = [0, 1, 2].map(i => (lo[i] + hi[i]) / 2);
    const R = 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    const home = S.view ? {az: S.view.az, el: S.view.el, zoom: 1} :
      {az: Math.atan2(1.3, 1.5), el: Math.atan2(0.9, Math.hypot(1.5, 1.3)), zoom: 1};
    const cam = Object.assign({}, home);
    const tk = [0, 1, 2].map(i => ticks(lo[i], hi[i], 4));
    const layers = S.layers.map(L => {
      const o = Object.assign({}, L);
      o.on = L.visible !== false;
      o.rgb = rgb(L.colour);
      if (L.type === "mesh") {
        o.v = f32(L.v); o.f = u32(L.f); o.buf = new Float32Array(o.v.length);
        let big = 0;
        for (const x of o.v) big = Math.max(big, Math.abs(x));
        o.tiny = 1e-9 * big * big;  // |n| of a degenerate (zero-area) triangle: skipped
      }
      if (L.type === "line" || L.type === "vec" || L.type === "point" || L.type === "rig") o.v = f32(L.v);
      if (L.type === "trail") { o.v = f32(L.v); o.tt = f32(L.tt); }
      return o;
    });
    // legend: one item per group, click toggles every layer of the group
    const groups = new Map();
    layers.forEach(L => {
      if (!L.legend) return;
      const g = L.group || L.name;
      if (!groups.has(g)) groups.set(g, {name: L.legend === true ? L.name : L.legend, colour: L.colour, on: L.on});
    });
    for (const [g, it] of groups) {
      const item = el("span", {class: "pv-item" + (it.on ? "" : " off"), "data-group": g}, legend);
      el("i", {style: "background:" + it.colour}, item);
      item.appendChild(document.createTextNode(it.name));
      item.addEventListener("click", () => {
        it.on = !it.on;
        item.classList.toggle("off", !it.on);
        layers.forEach(L => { if ((L.group || L.name) === g) L.on = it.on; });
        draw(frame);
      });
    }
    let frame = 0, W = 0, H = 0, proj = null;
    const labels = [];  // the axis titles drawn (read by the browser test)

    function size() {
      const dpr = window.devicePixelRatio || 1;
      W = root.clientWidth || 600;
      H = Math.round(Math.min(W, Math.max(360, 0.78 * window.innerHeight)));
      canvas.style.width = W + "px";
      canvas.style.height = H + "px";
      canvas.width = Math.round(W * dpr);
      canvas.height = Math.round(H * dpr);
      ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    }

    function draw(f) {
      frame = f;
      const ca = Math.cos(cam.az), sa = Math.sin(cam.az), ce = Math.cos(cam.el), se = Math.sin(cam.el);
      const d = [ce * ca, ce * sa, se], rt = [-sa, ca, 0], up = [-se * ca, -se * sa, ce];
      const s = cam.zoom * Math.min(W, H) / (2.05 * R), X0 = W / 2, Y0 = H / 2;
      const light = [0.45 * d[0] + 0.3 * rt[0] + 0.55 * up[0], 0.45 * d[1] + 0.3 * rt[1] + 0.55 * up[1],
                     0.45 * d[2] + 0.55 * up[2]];
      const ln = Math.hypot(light[0], light[1], light[2]);
      const P = (x, y, z) => {
        x -= c[0]; y -= c[1]; z -= c[2];
        return [X0 + s * (x * rt[0] + y * rt[1] + z * rt[2]),
                Y0 - s * (x * up[0] + y * up[1] + z * up[2]),
                x * d[0] + y * d[1] + z * d[2]];
      };
      proj = P;
      ctx.clearRect(0, 0, W, H);
      ctx.fillStyle = "#ffffff";
      ctx.fillRect(0, 0, W, H);
      box(P, d);
      const prims = [];
      const o = 4 * f;
      for (const L of layers) {
        if (!L.on) continue;
        const qq = L.frame === "ref" ? qref : q;
        const col = L.rgb;
        // a body that also moves (a six-degree-of-freedom motion): its centre at bp
        const ox = bp && L.frame !== "space" && L.frame !== "ref" ? bp[3 * f] : 0;
        const oy = bp && L.frame !== "space" && L.frame !== "ref" ? bp[3 * f + 1] : 0;
        const oz = bp && L.frame !== "space" && L.frame !== "ref" ? bp[3 * f + 2] : 0;
        if (L.type === "mesh") {
          const v = L.v, b = L.buf, m = v.length / 3, pts = new Array(m);
          for (let k = 0; k < m; k++) {
            if (L.frame === "space") { b[3 * k] = v[3 * k]; b[3 * k + 1] = v[3 * k + 1]; b[3 * k + 2] = v[3 * k + 2]; }
            else {
              qrot(qq, o, v[3 * k], v[3 * k + 1], v[3 * k + 2], b, 3 * k);
              b[3 * k] += ox; b[3 * k + 1] += oy; b[3 * k + 2] += oz;
            }
            pts[k] = P(b[3 * k], b[3 * k + 1], b[3 * k + 2]);
          }
          const F = L.f;
          for (let k = 0; k < F.length; k += 3) {
            const i = F[k], j = F[k + 1], l = F[k + 2];
            const ax = b[3 * j] - b[3 * i], ay = b[3 * j + 1] - b[3 * i + 1], az = b[3 * j + 2] - b[3 * i + 2];
            const bx = b[3 * l] - b[3 * i], by = b[3 * l + 1] - b[3 * i + 1], bz = b[3 * l + 2] - b[3 * i + 2];
            const nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
            const area2 = Math.hypot(nx, ny, nz);
            if (!(area2 > L.tiny)) continue;
            const nn = area2 * ln;
            const sh = 0.38 + 0.62 * Math.abs((nx * light[0] + ny * light[1] + nz * light[2]) / nn);
            prims.push({z: (pts[i][2] + pts[j][2] + pts[l][2]) / 3, t: 0, p: [pts[i], pts[j], pts[l]],
                        c: "rgba(" + Math.round(col[0] * sh) + "," + Math.round(col[1] * sh) + "," +
                           Math.round(col[2] * sh) + "," + (L.opacity || 1) + ")", a: L.opacity || 1});
          }
        } else if (L.type === "seg" || L.type === "vec") {
          let a = L.a || [0, 0, 0], e;
          if (L.type === "vec") {
            e = [L.v[3 * f], L.v[3 * f + 1], L.v[3 * f + 2]];
            if (bp) { a = [a[0] + ox, a[1] + oy, a[2] + oz]; e = [e[0] + ox, e[1] + oy, e[2] + oz]; }
          }
          else { e = [0, 0, 0]; qrot(qq, o, L.b[0], L.b[1], L.b[2], e, 0); }
          if (L.type === "seg" && L.frame === "space") e = L.b;
          else if (L.type === "seg" && bp) { a = [a[0] + ox, a[1] + oy, a[2] + oz]; e = [e[0] + ox, e[1] + oy, e[2] + oz]; }
          const n = 8;
          let p0 = P(a[0], a[1], a[2]);
          for (let k = 1; k <= n; k++) {
            const u = k / n, p1 = P(a[0] + u * (e[0] - a[0]), a[1] + u * (e[1] - a[1]), a[2] + u * (e[2] - a[2]));
            prims.push({z: (p0[2] + p1[2]) / 2, t: 1, p: [p0, p1], c: L.colour, w: L.width || 3, dash: L.dash});
            p0 = p1;
          }
          if (L.arrow) {
            const pa = P(a[0], a[1], a[2]);
            prims.push({z: p0[2] + 1e-9, t: 3, p: [pa, p0], c: L.colour, w: L.width || 3});
          }
        } else if (L.type === "line") {
          const v = L.v;
          let m = v.length / 3;
          if (L.upto) m = L.upto[f];
          const body = L.frame === "body", tmp = [0, 0, 0];
          let p0 = null;
          for (let k = 0; k < m; k++) {
            let x = v[3 * k], y = v[3 * k + 1], z = v[3 * k + 2];
            if (body) { qrot(qq, o, x, y, z, tmp, 0); x = tmp[0] + ox; y = tmp[1] + oy; z = tmp[2] + oz; }
            const p1 = P(x, y, z);
            if (p0) prims.push({z: (p0[2] + p1[2]) / 2, t: 1, p: [p0, p1], c: L.colour, w: L.width || 2});
            p0 = p1;
          }
        } else if (L.type === "trail") {  // the path up to the frame, fading with age
          const v = L.v, m = L.upto[f], now = L.tt[Math.max(0, m - 1)];
          let p0 = null;
          for (let k = 0; k < m; k++) {
            const p1 = P(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
            if (p0) {
              const a = L.floor + (1 - L.floor) * Math.exp(-(now - L.tt[k]) / L.tau);
              prims.push({z: (p0[2] + p1[2]) / 2, t: 1, p: [p0, p1], w: L.width || 2,
                          c: "rgba(" + col[0] + "," + col[1] + "," + col[2] + "," + a.toFixed(3) + ")"});
            }
            p0 = p1;
          }
        } else if (L.type === "rig") {  // m points at this frame, links between them
          const v = L.v, m = L.m, b = 3 * m * f;
          const pts = [];
          for (let k = 0; k < m; k++) pts.push(P(v[b + 3 * k], v[b + 3 * k + 1], v[b + 3 * k + 2]));
          for (const [i, j] of L.pairs) {
            if (!isFinite(pts[i][0] + pts[j][0] + pts[i][1] + pts[j][1])) continue;
            prims.push({z: (pts[i][2] + pts[j][2]) / 2, t: 1, p: [pts[i], pts[j]], c: L.colour,
                        w: L.width || 3, dash: L.dash});
          }
          if (L.dots) {
            pts.forEach((p, k) => {
              const big = (L.big || []).includes(k);
              if (isFinite(p[0] + p[1])) prims.push({z: p[2] + 1e-6, t: 2, p: [p], sym: "dot",
                                                     c: big ? L.dot : L.colour, w: big ? 6.5 : 3.5});
            });
          }
        } else if (L.type === "marker" || L.type === "point") {
          const p = L.type === "point" ? [L.v[3 * f], L.v[3 * f + 1], L.v[3 * f + 2]] : L.p;
          prims.push({z: P(p[0], p[1], p[2])[2] + 1e-6, t: 2, p: [P(p[0], p[1], p[2])], c: L.colour,
                      sym: L.symbol || "dot", w: L.size || 5});
        }
      }
      prims.sort((A, B) => A.z - B.z);
      ctx.lineCap = "round";
      ctx.lineJoin = "round";
      for (const pr of prims) {
        const p = pr.p;
        if (pr.t === 0) {
          ctx.beginPath();
          ctx.moveTo(p[0][0], p[0][1]); ctx.lineTo(p[1][0], p[1][1]); ctx.lineTo(p[2][0], p[2][1]);
          ctx.closePath();
          ctx.fillStyle = pr.c;
          ctx.fill();
          if (pr.a >= 1) { ctx.strokeStyle = pr.c; ctx.lineWidth = 0.6; ctx.setLineDash([]); ctx.stroke(); }
        } else if (pr.t === 1) {
          ctx.beginPath();
          ctx.moveTo(p[0][0], p[0][1]); ctx.lineTo(p[1][0], p[1][1]);
          ctx.strokeStyle = pr.c; ctx.lineWidth = pr.w;
          ctx.setLineDash(pr.dash ? [6, 5] : []);
          ctx.stroke();
        } else if (pr.t === 3) {  // arrow head at p[1], pointing away from p[0]
          const dx = p[1][0] - p[0][0], dy = p[1][1] - p[0][1], L = Math.hypot(dx, dy);
          if (L < 1) continue;
          const ux = dx / L, uy = dy / L, h = Math.min(14, 0.35 * L), wd = 0.45 * h;
          ctx.beginPath();
          ctx.moveTo(p[1][0] + ux * h * 0.3, p[1][1] + uy * h * 0.3);
          ctx.lineTo(p[1][0] - ux * h - uy * wd, p[1][1] - uy * h + ux * wd);
          ctx.lineTo(p[1][0] - ux * h + uy * wd, p[1][1] - uy * h - ux * wd);
          ctx.closePath();
          ctx.fillStyle = pr.c; ctx.fill();
        } else {
          const x = p[0][0], y = p[0][1], r = pr.w;
          ctx.setLineDash([]);
          ctx.fillStyle = pr.c; ctx.strokeStyle = pr.c; ctx.lineWidth = 2;
          ctx.beginPath();
          if (pr.sym === "diamond") {
            ctx.moveTo(x, y - r * 1.3); ctx.lineTo(x + r, y); ctx.lineTo(x, y + r * 1.3); ctx.lineTo(x - r, y);
            ctx.closePath(); ctx.fill();
          } else if (pr.sym === "cross") {
            ctx.moveTo(x - r, y); ctx.lineTo(x + r, y); ctx.moveTo(x, y - r); ctx.lineTo(x, y + r); ctx.stroke();
          } else { ctx.arc(x, y, r, 0, 2 * Math.PI); ctx.fill(); }
        }
      }
      ctx.setLineDash([]);
    }

    // the axes box: back planes with a grid, ticks and titles on the front-bottom edges
    function box(P, d) {
      const B = [lo, hi];
      ctx.lineWidth = 1;
      ctx.setLineDash([]);
      for (let a = 0; a < 3; a++) {  // back plane normal to axis a, grid of the other two
        const va = d[a] > 0 ? lo[a] : hi[a];
        const b1 = (a + 1) % 3, b2 = (a + 2) % 3;
        ctx.fillStyle = "rgba(229,236,246,0.55)";
        const corner = (u, v) => { const p = [0, 0, 0]; p[a] = va; p[b1] = u; p[b2] = v; return P(p[0], p[1], p[2]); };
        const cs = [corner(lo[b1], lo[b2]), corner(hi[b1], lo[b2]), corner(hi[b1], hi[b2]), corner(lo[b1], hi[b2])];
        ctx.beginPath(); ctx.moveTo(cs[0][0], cs[0][1]);
        for (let k = 1; k < 4; k++) ctx.lineTo(cs[k][0], cs[k][1]);
        ctx.closePath(); ctx.fill();
        ctx.strokeStyle = "#ffffff";
        for (const [bb, other] of [[b1, b2], [b2, b1]]) {
          for (const x of tk[bb].v) {
            const p = [0, 0, 0], r = [0, 0, 0];
            p[a] = r[a] = va; p[bb] = r[bb] = x; p[other] = lo[other]; r[other] = hi[other];
            const A = P(p[0], p[1], p[2]), Bp = P(r[0], r[1], r[2]);
            ctx.beginPath(); ctx.moveTo(A[0], A[1]); ctx.lineTo(Bp[0], Bp[1]); ctx.stroke();
          }
        }
      }
      const pc = P(c[0], c[1], c[2]);
      const text = (str, x, y) => {  // centred on (x, y), kept inside the canvas
        const h = ctx.measureText(str).width / 2 + 2;
        ctx.fillText(str, Math.max(h, Math.min(W - h, x)), Math.max(8, Math.min(H - 8, y)));
      };
      ctx.font = "11px system-ui, sans-serif";
      ctx.fillStyle = "#444";
      for (let a = 0; a < 3; a++) {  // the labelled edge: lowest on screen (x, y), leftmost (z)
        const b1 = (a + 1) % 3, b2 = (a + 2) % 3;
        let best = null, score = -Infinity;
        for (const u of B) for (const v of B) {
          const p = [0, 0, 0]; p[a] = c[a]; p[b1] = u[b1]; p[b2] = v[b2];
          const m = P(p[0], p[1], p[2]);
          const sc = a === 2 ? -m[0] : m[1];
          if (sc > score) { score = sc; best = p; }
        }
        const ends = [0, 1].map(k => { const p = best.slice(); p[a] = B[k][a]; return P(p[0], p[1], p[2]); });
        ctx.strokeStyle = "#888";
        ctx.beginPath(); ctx.moveTo(ends[0][0], ends[0][1]); ctx.lineTo(ends[1][0], ends[1][1]); ctx.stroke();
        const mid = P(best[0], best[1], best[2]);
        let ox = mid[0] - pc[0], oy = mid[1] - pc[1];
        const on = Math.hypot(ox, oy) || 1;
        ox /= on; oy /= on;
        ctx.textAlign = "center"; ctx.textBaseline = "middle";
        const big = Math.max(Math.abs(lo[a]), Math.abs(hi[a]));
        for (const x of tk[a].v) {
          const p = best.slice(); p[a] = x;
          const m = P(p[0], p[1], p[2]);
          ctx.beginPath(); ctx.moveTo(m[0], m[1]); ctx.lineTo(m[0] + 5 * ox, m[1] + 5 * oy); ctx.stroke();
          text(fmtTick(x, tk[a].step, big), m[0] + 16 * ox, m[1] + 13 * oy);
        }
        ctx.font = "bold 12px system-ui, sans-serif";
        labels[a] = "xyz"[a] + " (" + S.unit + ")";
        text(labels[a], mid[0] + 60 * ox, mid[1] + 34 * oy);
        ctx.font = "11px system-ui, sans-serif";
      }
    }

    // interaction
    let drag = null;
    canvas.addEventListener("pointerdown", e => { drag = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
    canvas.addEventListener("pointermove", e => {
      if (!drag) return;
      cam.az -= 0.01 * (e.clientX - drag[0]);
      cam.el = Math.max(-1.55, Math.min(1.55, cam.el + 0.01 * (e.clientY - drag[1])));
      drag = [e.clientX, e.clientY];
      draw(frame);
    });
    canvas.addEventListener("pointerup", () => { drag = null; });
    canvas.addEventListener("wheel", e => {
      e.preventDefault();
      cam.zoom = Math.max(0.2, Math.min(20, cam.zoom * Math.exp(-0.0015 * e.deltaY)));
      draw(frame);
    }, {passive: false});
    canvas.addEventListener("dblclick", () => { Object.assign(cam, home); draw(frame); });
    size();
    // where a space point is drawn (CSS pixels in the canvas) at the current view
    const project = (x, y, z) => proj(x, y, z).slice(0, 2);
    return {draw, size, canvas, layers, cam, labels, project, redraw: () => draw(frame)};
  }

  // ------------------------------------------------------------------ a chart
  // A time series by default (x = t in s, a cursor at the frame's time); with
  // panel.xtitle, any x. Series modes: "line" (default), "markers" (points), "bars"
  // (x holds the k + 1 bin edges, y the k heights).
  function Chart(root, panel, t0, t1, k) {
    const box = el("div", {class: "pv-panel", id: "poinsot-panel-" + k}, root);
    el("div", {class: "pv-title"}, box).textContent = panel.title;
    const legend = el("div", {class: "pv-legend"}, box);
    const holder = el("div", {class: "pv-chart"}, box);
    const tip = el("div", {class: "pv-tip"}, holder);
    const series = panel.series.map(s => Object.assign({}, s, {x: f32(s.x), y: f32(s.y), on: true}));
    const timed = !panel.xtitle;
    if (!timed) {  // the x range of the data
      t0 = Infinity; t1 = -Infinity;
      for (const s of series) for (const v of s.x) if (isFinite(v)) { t0 = Math.min(t0, v); t1 = Math.max(t1, v); }
      if (!isFinite(t0)) { t0 = 0; t1 = 1; }
      if (series.some(s => s.mode === "markers")) { const h = 0.03 * (t1 - t0 || 1); t0 -= h; t1 += h; }
    }
    series.forEach(s => {
      const item = el("span", {class: "pv-item"}, legend);
      el("i", {style: "background:" + s.colour}, item);
      item.appendChild(document.createTextNode(s.name));
      item.addEventListener("click", () => {
        s.on = !s.on;
        item.classList.toggle("off", !s.on);
        render();
      });
    });
    let svg = null, cursor = null, hover = null, now = t0, geo = null;
    const H = 230, m = {l: 70, r: 14, t: 10, b: 40};

    function render() {
      if (svg) svg.remove();
      const W = Math.max(260, holder.clientWidth || 500);
      svg = el("svg", {width: W, height: H, viewBox: "0 0 " + W + " " + H}, holder, SVGNS);
      let ylo = Infinity, yhi = -Infinity;
      for (const s of series) {
        if (!s.on) continue;
        for (const v of s.y) if (isFinite(v)) { if (v < ylo) ylo = v; if (v > yhi) yhi = v; }
      }
      if (series.some(s => s.on && s.mode === "bars")) ylo = Math.min(ylo, 0);
      if (!isFinite(ylo)) { ylo = -1; yhi = 1; }
      if (yhi - ylo <= 1e-12 * Math.max(Math.abs(ylo), Math.abs(yhi))) {
        const h = Math.abs(ylo) * 0.1 || 1; ylo -= h; yhi += h;
      } else { const h = 0.05 * (yhi - ylo); ylo -= h; yhi += h; }
      const xlo = t0, xhi = t1 > t0 ? t1 : t0 + 1;
      const pw = W - m.l - m.r, ph = H - m.t - m.b;
      const sx = x => m.l + (x - xlo) / (xhi - xlo) * pw, sy = y => m.t + (yhi - y) / (yhi - ylo) * ph;
      geo = {sx, sy, xlo, xhi, pw, ph};
      el("rect", {x: m.l, y: m.t, width: pw, height: ph, fill: "#f6f8fb", stroke: "#ccd"}, svg, SVGNS);
      const tx = ticks(xlo, xhi, Math.max(3, Math.round(pw / 90))), ty = ticks(ylo, yhi, 5);
      const bigx = Math.max(Math.abs(xlo), Math.abs(xhi)), bigy = Math.max(Math.abs(ylo), Math.abs(yhi));
      for (const x of tx.v) {
        el("line", {x1: sx(x), x2: sx(x), y1: m.t, y2: m.t + ph, stroke: "#e2e6ee"}, svg, SVGNS);
        const lab = el("text", {x: sx(x), y: m.t + ph + 15, "text-anchor": "middle", class: "pv-tick"}, svg, SVGNS);
        lab.textContent = fmtTick(x, tx.step, bigx);
      }
      for (const y of ty.v) {
        el("line", {x1: m.l, x2: m.l + pw, y1: sy(y), y2: sy(y), stroke: y === 0 ? "#b8bfcc" : "#e2e6ee"}, svg, SVGNS);
        const lab = el("text", {x: m.l - 5, y: sy(y) + 4, "text-anchor": "end", class: "pv-tick"}, svg, SVGNS);
        lab.textContent = fmtTick(y, ty.step, bigy);
      }
      const xt = el("text", {x: m.l + pw / 2, y: H - 6, "text-anchor": "middle", class: "pv-axis-title"}, svg, SVGNS);
      xt.textContent = timed ? "t (s)" : panel.xtitle;
      const yt = el("text", {x: 13, y: m.t + ph / 2, "text-anchor": "middle", class: "pv-axis-title",
                             transform: "rotate(-90 13 " + (m.t + ph / 2) + ")"}, svg, SVGNS);
      yt.textContent = panel.ytitle;
      const clip = "pv-clip-" + k;
      const defs = el("defs", {}, svg, SVGNS);
      el("rect", {x: m.l, y: m.t, width: pw, height: ph}, el("clipPath", {id: clip}, defs, SVGNS), SVGNS);
      for (const s of series) {
        if (!s.on) continue;
        if (s.mode === "bars") {
          const g = el("g", {fill: s.colour, "fill-opacity": 0.85, class: "pv-series"}, svg, SVGNS);
          for (let i = 0; i < s.y.length; i++) {
            const x0 = sx(s.x[i]), x1 = sx(s.x[i + 1]), y0 = sy(Math.max(s.y[i], ylo));
            el("rect", {x: x0 + 0.5, y: y0, width: Math.max(0.5, x1 - x0 - 1), height: sy(ylo) - y0}, g, SVGNS);
          }
          continue;
        }
        if (s.mode === "markers") {
          const g = el("g", {fill: s.colour, "fill-opacity": 0.6, class: "pv-series"}, svg, SVGNS);
          for (let i = 0; i < s.x.length; i++) {
            if (isFinite(s.x[i]) && isFinite(s.y[i])) {
              el("circle", {cx: sx(s.x[i]).toFixed(1), cy: sy(s.y[i]).toFixed(1), r: 2.2}, g, SVGNS);
            }
          }
          continue;
        }
        const pts = [];
        for (let i = 0; i < s.x.length; i++) {
          if (isFinite(s.y[i])) pts.push(sx(s.x[i]).toFixed(1) + "," + sy(s.y[i]).toFixed(1));
        }
        const a = {points: pts.join(" "), fill: "none", stroke: s.colour, "stroke-width": 1.7,
                   "clip-path": "url(#" + clip + ")", class: "pv-series"};
        if (s.dash) a["stroke-dasharray"] = s.dash === "dot" ? "2 3" : "6 4";
        el("polyline", a, svg, SVGNS);
      }
      cursor = timed ? el("line", {y1: m.t, y2: m.t + ph, stroke: "rgba(0,0,0,0.55)", "stroke-width": 1.5,
                                   "stroke-dasharray": "4 3", class: "pv-cursor"}, svg, SVGNS) : null;
      hover = el("line", {y1: m.t, y2: m.t + ph, stroke: "#888", "stroke-width": 1, visibility: "hidden"}, svg, SVGNS);
      const cap = el("rect", {x: m.l, y: m.t, width: pw, height: ph, fill: "transparent"}, svg, SVGNS);
      cap.addEventListener("mousemove", e => read(e));
      cap.addEventListener("mouseleave", () => { tip.style.display = "none"; hover.setAttribute("visibility", "hidden"); });
      setTime(now);
    }
    function nearest(x, v) {
      let a = 0, b = x.length - 1;
      while (b - a > 1) { const h = (a + b) >> 1; if (x[h] < v) a = h; else b = h; }
      return Math.abs(x[a] - v) <= Math.abs(x[b] - v) ? a : b;
    }
    function read(e) {
      const r = svg.getBoundingClientRect(), px = e.clientX - r.left;
      const py = e.clientY - r.top;
      const tt = geo.xlo + (px - m.l) / geo.pw * (geo.xhi - geo.xlo);
      const u = panel.unit ? " " + panel.unit : "", xu = panel.xunit ? " " + panel.xunit : "";
      const lines = [timed ? "t = " + fmtVal(tt) + " s" : panel.xname + " = " + fmtVal(tt) + xu];
      for (const s of series) {
        if (!s.on || !s.x.length) continue;
        const head = '<span style="color:' + s.colour + '">\u25a0</span> ' + s.name.replace(/</g, "&lt;");
        if (s.mode === "bars") {
          let i = 0, b = s.x.length - 1;  // the bin [x[i], x[i + 1]) holding tt
          while (b - i > 1) { const h = (i + b) >> 1; if (s.x[h] <= tt) i = h; else b = h; }
          lines.push(head + ": " + fmtVal(s.y[i]) + u + " in [" + fmtVal(s.x[i]) + ", " + fmtVal(s.x[i + 1]) + ")" + xu);
        } else if (s.mode === "markers") {  // the nearest point on screen
          let best = -1, dmin = Infinity;
          for (let i = 0; i < s.x.length; i++) {
            const d = Math.hypot(geo.sx(s.x[i]) - px, geo.sy(s.y[i]) - py);
            if (d < dmin) { dmin = d; best = i; }
          }
          if (best >= 0) {
            lines.push(head + ": (" + fmtVal(s.x[best]) + xu + ", " + fmtVal(s.y[best]) + u + ")");
          }
        } else {
          lines.push(head + ": " + fmtVal(s.y[nearest(s.x, tt)]) + u);
        }
      }
      tip.innerHTML = lines.join("<br>");
      tip.style.display = "block";
      tip.style.left = Math.min(px + 14, (holder.clientWidth || 500) - 200) + "px";
      tip.style.top = (e.clientY - r.top + 10) + "px";
      hover.setAttribute("x1", px); hover.setAttribute("x2", px);
      hover.setAttribute("visibility", "visible");
    }
    function setTime(tt) {
      now = tt;
      if (!cursor) return;
      const x = geo.sx(Math.max(geo.xlo, Math.min(geo.xhi, tt)));
      cursor.setAttribute("x1", x); cursor.setAttribute("x2", x);
    }
    render();
    return {render, setTime, box, series};
  }

  // ------------------------------------------------------------------ the page
  function start() {
    const P = JSON.parse(document.getElementById("poinsot-data").textContent);
    const g = document.getElementById("poinsot-figure");
    const t = f32(P.t), q = f32(P.q), qref = f32(P.qref), bp = P.bp ? f32(P.bp) : null;
    const n = t.length;
    const sceneCol = document.getElementById("poinsot-scene-col");
    const panelCol = document.getElementById("poinsot-panels");
    const scene = P.scene ? Scene(sceneCol, P.scene, q, qref, bp) : null;
    if (!scene) { sceneCol.remove(); g.classList.add("pv-noscene"); }
    const charts = P.panels.map((p, k) => Chart(panelCol, p, P.t0, P.t1, k));
    const slider = document.getElementById("poinsot-slider");
    const label = document.getElementById("poinsot-time");
    const play = document.getElementById("poinsot-play");
    const speed = document.getElementById("poinsot-speed");
    window.poinsotViewer = {scene, charts, data: P};
    window.addEventListener("resize", () => {
      clearTimeout(window.poinsotViewer.rs);
      window.poinsotViewer.rs = setTimeout(() => {
        if (scene) { scene.size(); scene.redraw(); }
        charts.forEach(ch => ch.render());
      }, 150);
    });
    if (!slider || n === 0) {  // charts only (e.g. an ensemble's histograms): no animation
      window.poinsotFrames = 0;
      g.dataset.ready = "1";
      return;
    }
    slider.max = String(Math.max(0, n - 1));
    function draw(f) {
      f = Math.max(0, Math.min(n - 1, f | 0));
      if (scene) scene.draw(f);
      for (const ch of charts) ch.setTime(t[f]);
      slider.value = String(f);
      label.textContent = "t = " + (+t[f].toPrecision(4)) + " s";
      g.dataset.frame = String(f);
    }
    let timer = null;
    function stop() {
      if (timer) { clearInterval(timer); timer = null; }
      play.textContent = "\u25b6 Play";
    }
    function tick() {
      const s = +speed.value, step = s > 1 ? Math.round(s) : 1;
      let f = +slider.value + step;
      if (f >= n) { f = n - 1; stop(); }
      draw(f);
    }
    play.addEventListener("click", () => {
      if (timer) { stop(); return; }
      if (+slider.value >= n - 1) draw(0);
      timer = setInterval(tick, Math.round(P.interval / Math.min(+speed.value, 1)));
      play.textContent = "\u275a\u275a Pause";
    });
    speed.addEventListener("change", () => { if (timer) { stop(); play.click(); } });
    slider.addEventListener("input", () => draw(+slider.value));
    window.poinsotDraw = draw;
    window.poinsotFrames = n;
    draw(0);
    g.dataset.ready = "1";
  }
  try { start(); } catch (e) {
    console.error(e);
    document.getElementById("poinsot-error").textContent = "The report could not start: " + e;
  }
})();
