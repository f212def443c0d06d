// Trajectory player of the funnel report: draws a logged trajectory on a canvas and plays it.
// The motion between events follows funnel/motion.py exactly: parabolas in flight, a cubic
// Hermite along the face during a sustained contact, an arc about the edge point during an edge
// contact; the spin angle advances by omega * dt in flight and with the mean spin in contacts.
// Data: <script type="application/json" id="player-data-ID"> next to <div class="player" id="player-ID">,
// written by funnel.report from the figure's CSV and JSON. No network, no libraries.
"use strict";

const FunnelPlayer = (() => {
  const FLIGHT = 0, FACE = 1, EDGE = 2;

  function segments(g, ev) {
    const n = ev.time.length;
    const xr = (g.release !== undefined && g.release !== null && g.half_width !== undefined)
      ? g.release * g.half_width : (n ? ev.x[0] : 0);
    const s = {n, t0: [], t1: [], x0: [], y0: [], x1: [], y1: [], u0: [], v0: [], w0: [], u1: [], v1: [], w1: [],
               kind: [], ex: [], ey: [], phi0: []};
    let phi = 0;
    for (let i = 0; i < n; i++) {
      const p = i - 1;
      s.t0.push(p < 0 ? 0 : ev.time[p]);
      s.t1.push(ev.time[i]);
      s.x0.push(p < 0 ? xr : ev.x[p]);
      s.y0.push(p < 0 ? g.y_release : ev.y[p]);
      s.x1.push(ev.x[i]);
      s.y1.push(ev.y[i]);
      s.u0.push(p < 0 ? 0 : ev.u_after[p]);
      s.v0.push(p < 0 ? 0 : ev.v_after[p]);
      s.w0.push(p < 0 ? 0 : ev.omega_after[p]);
      s.u1.push(ev.u_before[i]);
      s.v1.push(ev.v_before[i]);
      s.w1.push(ev.omega_before[i]);
      const start = p < 0 ? "release" : ev.kind[p];
      const kind = start === "contact_start" ? FACE : start === "edge_contact_start" ? EDGE : FLIGHT;
      s.kind.push(kind);
      const left = p >= 0 && ev.wall[p] === "left";
      s.ex.push(kind === EDGE ? (left ? -g.half_gap : g.half_gap) : 0);
      s.ey.push(kind === EDGE ? g.y_bottom : 0);
      s.phi0.push(phi);
      const dt = s.t1[i] - s.t0[i];
      phi += kind === FLIGHT ? s.w0[i] * dt : 0.5 * (s.w0[i] + s.w1[i]) * dt;
    }
    return s;
  }

  function hermite(p0, p1, m0, m1, u, dt) {
    const u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * dt * m0 + (-2 * u3 + 3 * u2) * p1 + (u3 - u2) * dt * m1;
  }

  // Centre of segment i at time tau after its start (fraction u); alongPath: uniform along the path.
  function position(s, i, tau, u, alongPath) {
    const dt = s.t1[i] - s.t0[i];
    if (s.kind[i] === FACE) {
      if (alongPath) return [s.x0[i] + (s.x1[i] - s.x0[i]) * u, s.y0[i] + (s.y1[i] - s.y0[i]) * u];
      return [hermite(s.x0[i], s.x1[i], s.u0[i], s.u1[i], u, dt), hermite(s.y0[i], s.y1[i], s.v0[i], s.v1[i], u, dt)];
    }
    if (s.kind[i] === EDGE) {
      const dx0 = s.x0[i] - s.ex[i], dy0 = s.y0[i] - s.ey[i], dx1 = s.x1[i] - s.ex[i], dy1 = s.y1[i] - s.ey[i];
      const a0 = Math.atan2(dy0, dx0), r0 = Math.hypot(dx0, dy0), r1 = Math.hypot(dx1, dy1);
      let turn = Math.atan2(dy1, dx1) - a0;
      turn = ((turn + Math.PI) % (2 * Math.PI) + 2 * Math.PI) % (2 * Math.PI) - Math.PI;
      let alpha;
      if (alongPath) {
        alpha = a0 + turn * u;
      } else {
        const w0 = (dx0 * s.v0[i] - dy0 * s.u0[i]) / Math.max(r0 * r0, 1e-300);
        const w1 = (dx1 * s.v1[i] - dy1 * s.u1[i]) / Math.max(r1 * r1, 1e-300);
        alpha = hermite(a0, a0 + turn, w0, w1, u, dt);
      }
      const r = r0 + (r1 - r0) * u;
      return [s.ex[i] + r * Math.cos(alpha), s.ey[i] + r * Math.sin(alpha)];
    }
    return [s.x0[i] + s.u0[i] * tau, s.y0[i] + s.v0[i] * tau - 0.5 * tau * tau];
  }

  // [x, y, phi] at time t (clipped to the trajectory), like funnel.motion.state_at.
  function stateAt(s, t) {
    if (s.n === 0) return [0, 0, 0];
    t = Math.min(Math.max(t, 0), s.t1[s.n - 1]);
    let lo = 0, hi = s.n - 1;  // first i with t1[i] >= t
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (s.t1[mid] < t) lo = mid + 1; else hi = mid;
    }
    const i = lo, dt = s.t1[i] - s.t0[i], tau = t - s.t0[i];
    const u = dt > 0 ? tau / dt : 1;
    const [x, y] = position(s, i, tau, u, false);
    const slope = s.kind[i] !== FLIGHT && dt > 0 ? (s.w1[i] - s.w0[i]) / dt : 0;
    return [x, y, s.phi0[i] + s.w0[i] * tau + 0.5 * slope * tau * tau];
  }

  // The path sampled for drawing: k points per segment; returns {x, y, t} arrays.
  function path(s, k) {
    const x = [], y = [], t = [];
    for (let i = 0; i < s.n; i++) {
      const dt = s.t1[i] - s.t0[i];
      for (let j = 0; j < k; j++) {
        const u = j / (k - 1);
        const p = position(s, i, dt * u, u, true);
        x.push(p[0]);
        y.push(p[1]);
        t.push(s.t0[i] + dt * u);
      }
    }
    return {x, y, t};
  }

  function element(tag, attrs, parent) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (k === "text") e.textContent = v; else e.setAttribute(k, v);
    }
    if (parent) parent.appendChild(e);
    return e;
  }

  class Player {
    constructor(root, data) {
      this.data = data;
      this.panels = data.panels.map((p) => {
        const s = segments(p.geometry, p.events);
        const k = s.n < 2000 ? 24 : 6;
        return {p, s, path: path(s, k), tEnd: s.n ? s.t1[s.n - 1] : 0};
      });
      this.index = 0;
      this.t = 0;
      this.playing = false;
      this.last = null;
      const bar = element("div", {class: "player-controls"}, root);
      this.select = element("select", {"aria-label": "trajectory"}, bar);
      this.panels.forEach((q, i) => element("option", {value: String(i), text: `(${q.p.id}) ${q.p.label}`}, this.select));
      this.button = element("button", {type: "button", text: "▶ play"}, bar);
      this.range = element("input", {type: "range", min: "0", max: "10000", step: "1", value: "0",
                                     "aria-label": "time"}, bar);
      element("label", {text: " speed "}, bar);
      this.speed = element("select", {"aria-label": "speed"}, bar);
      for (const v of [0.0625, 0.125, 0.25, 0.5, 1, 2, 4, 8, 16, 32, 64]) {
        const o = element("option", {value: String(v), text: `${v} √(H/g) per s`}, this.speed);
        if (v === 4) o.selected = true;
      }
      this.readout = element("span", {class: "player-time"}, bar);
      this.canvas = element("canvas", {width: "760", height: "460"}, root);
      this.canvas.style.maxWidth = "100%";
      this.select.addEventListener("change", () => { this.index = Number(this.select.value); this.seek(0); });
      this.button.addEventListener("click", () => (this.playing ? this.pause() : this.play()));
      this.range.addEventListener("input", () => this.seek(Number(this.range.value) / 10000 * this.current().tEnd));
      this.draw();
    }

    current() { return this.panels[this.index]; }

    play() {
      if (this.t >= this.current().tEnd) this.t = 0;
      this.playing = true;
      this.button.textContent = "❚❚ pause";
      this.last = null;
      const step = (now) => {
        if (!this.playing) return;
        if (this.last !== null) this.t += (now - this.last) / 1000 * Number(this.speed.value);
        this.last = now;
        if (this.t >= this.current().tEnd) { this.t = this.current().tEnd; this.pause(); }
        this.draw();
        if (this.playing) requestAnimationFrame(step);
      };
      requestAnimationFrame(step);
    }

    pause() {
      this.playing = false;
      this.button.textContent = "▶ play";
      this.draw();
    }

    seek(t) {
      this.t = Math.min(Math.max(t, 0), this.current().tEnd);
      this.draw();
    }

    // Maps world coordinates (H) into a box of the canvas with equal scales.
    static view(box, x0, x1, y0, y1) {
      const scale = Math.min(box.w / (x1 - x0), box.h / (y1 - y0));
      const cx = box.x + box.w / 2, cy = box.y + box.h / 2, mx = (x0 + x1) / 2, my = (y0 + y1) / 2;
      return {scale, X: (x) => cx + (x - mx) * scale, Y: (y) => cy - (y - my) * scale};
    }

    drawScene(ctx, v, q, upto, trailFrom, ball, clipBox) {
      const g = q.p.geometry, th = g.theta * Math.PI / 180, top = g.y_release + 0.06;
      ctx.save();
      ctx.beginPath();
      ctx.rect(clipBox.x, clipBox.y, clipBox.w, clipBox.h);
      ctx.clip();
      ctx.lineWidth = 2;
      ctx.strokeStyle = "#000";
      for (const sign of [-1, 1]) {  // the walls, ending at the edge points
        const ex = sign * g.half_gap, ey = g.y_bottom, len = (top - ey) / Math.sin(th);
        ctx.beginPath();
        ctx.moveTo(v.X(ex), v.Y(ey));
        ctx.lineTo(v.X(ex + sign * Math.cos(th) * len), v.Y(top));
        ctx.stroke();
      }
      ctx.setLineDash([5, 4]);
      ctx.lineWidth = 0.8;
      ctx.strokeStyle = "#555";
      ctx.beginPath();
      ctx.moveTo(v.X(-g.half_width), v.Y(g.y_release));
      ctx.lineTo(v.X(g.half_width), v.Y(g.y_release));
      ctx.stroke();
      ctx.setLineDash([]);
      const P = q.path;
      ctx.lineWidth = 0.7;
      ctx.strokeStyle = "rgba(0, 114, 178, 0.18)";  // the whole path, faint
      ctx.beginPath();
      for (let j = 0; j < P.x.length; j++) (j ? ctx.lineTo : ctx.moveTo).call(ctx, v.X(P.x[j]), v.Y(P.y[j]));
      ctx.stroke();
      ctx.lineWidth = 0.8;
      ctx.strokeStyle = "rgba(0, 114, 178, 0.45)";  // the path so far
      ctx.beginPath();
      let j = 0;
      for (; j < P.x.length && P.t[j] <= upto; j++) (j ? ctx.lineTo : ctx.moveTo).call(ctx, v.X(P.x[j]), v.Y(P.y[j]));
      ctx.lineTo(v.X(ball[0]), v.Y(ball[1]));
      ctx.stroke();
      ctx.lineWidth = 1.8;
      ctx.strokeStyle = "#0072B2";  // the last few flights, bold
      ctx.beginPath();
      let k = 0;
      for (let m = 0; m < P.x.length && P.t[m] <= upto; m++) {
        if (P.t[m] < trailFrom) continue;
        (k++ ? ctx.lineTo : ctx.moveTo).call(ctx, v.X(P.x[m]), v.Y(P.y[m]));
      }
      if (k) ctx.lineTo(v.X(ball[0]), v.Y(ball[1]));
      ctx.stroke();
      const ev = q.p.events;
      ctx.fillStyle = "#000";
      for (let i = 0; i < ev.time.length && ev.time[i] <= upto; i++) {
        if (ev.kind[i] !== "face" && ev.kind[i] !== "edge") continue;
        ctx.beginPath();
        ctx.arc(v.X(ev.x[i]), v.Y(ev.y[i]), 1.6, 0, 2 * Math.PI);
        ctx.fill();
      }
      const r = Math.max(3, g.radius * v.scale);  // the ball, and its spin as a diameter and a dot
      const bx = v.X(ball[0]), by = v.Y(ball[1]), c = Math.cos(ball[2]), sn = Math.sin(ball[2]);
      ctx.fillStyle = "rgba(240, 200, 160, 0.9)";
      ctx.strokeStyle = "#D55E00";
      ctx.lineWidth = 1.2;
      ctx.beginPath();
      ctx.arc(bx, by, r, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
      if (r > 6) {
        ctx.strokeStyle = "#7a2e00";
        ctx.lineWidth = Math.max(1.5, r / 12);
        ctx.beginPath();
        ctx.moveTo(bx - r * c, by + r * sn);
        ctx.lineTo(bx + r * c, by - r * sn);
        ctx.stroke();
        ctx.fillStyle = "#7a2e00";
        ctx.beginPath();
        ctx.arc(bx + 0.7 * r * c, by - 0.7 * r * sn, Math.max(2, r / 7), 0, 2 * Math.PI);
        ctx.fill();
      }
      ctx.restore();
    }

    draw() {
      const q = this.current(), g = q.p.geometry, c = this.canvas, ctx = c.getContext("2d");
      const ball = stateAt(q.s, this.t);
      // The bold trail: from the start of the third flight before the current one.
      let i = 0;
      while (i < q.s.n - 1 && q.s.t1[i] < this.t) i++;
      const trailFrom = q.s.t0[Math.max(0, i - 2)];
      ctx.fillStyle = "#fff";
      ctx.fillRect(0, 0, c.width, c.height);
      const w = g.y_release / Math.tan(g.theta * Math.PI / 180) + 0.1;
      const main = {x: 8, y: 8, w: c.width - 236, h: c.height - 16};
      this.drawScene(ctx, Player.view(main, -w, w, Math.min(0, g.y_bottom) - 0.05, g.y_release + 0.1), q, this.t, trailFrom, ball, main);
      // A close-up that follows the ball, where the spin is visible (ball to scale).
      const zoom = {x: c.width - 220, y: 8, w: 212, h: 212}, half = 5 * g.radius;
      ctx.strokeStyle = "#999";
      ctx.lineWidth = 1;
      ctx.strokeRect(zoom.x, zoom.y, zoom.w, zoom.h);
      this.drawScene(ctx, Player.view(zoom, ball[0] - half, ball[0] + half, ball[1] - half, ball[1] + half), q, this.t, trailFrom, ball, zoom);
      ctx.fillStyle = "#333";
      ctx.font = "12px serif";
      ctx.fillText(`close-up: ${(2 * half).toPrecision(2)} H wide`, zoom.x + 4, zoom.y + zoom.h + 16);
      ctx.fillText(`(${q.p.id}) ${q.p.label}`, main.x + 4, main.y + 14);
      this.readout.textContent = ` t = ${this.t.toFixed(3)} of ${q.tEnd.toFixed(3)} √(H/g)`;
      this.range.value = String(q.tEnd > 0 ? Math.round(this.t / q.tEnd * 10000) : 0);
    }

    // For tests: [x, y, phi] of panel i at time t.
    stateAt(i, t) { return stateAt(this.panels[i].s, t); }
  }

  function mountAll() {
    const players = {};
    for (const root of document.querySelectorAll("div.player")) {
      const id = root.id.replace(/^player-/, "");
      const script = document.getElementById(`player-data-${id}`);
      if (!script) continue;
      players[id] = new Player(root, JSON.parse(script.textContent));
    }
    window.funnelPlayers = players;
    return players;
  }

  return {mountAll, stateAt, segments};
})();

FunnelPlayer.mountAll();
