// eulersym's animation player: draws a rigid body's motion on a 2-D canvas, from the data in the page.
// Plain JavaScript (ES2017), no library, no network: the page is the whole program.
//
// Data (the JSON in #eulersym-data), display frame (z up: the vertical, or L for a free body):
//   t[n]            frame times (s)
//   R[n][9]         body -> display rotation, row-major
//   w[n][3], L[n][3], trace[n][3]   omega and L arrows (scaled), the figure axis' tip
//   vertices[v][3], faces[f][k], faceTint[f], tints[c][3] (RGB)   the body, in body components
//   axes[3][3]      principal axes (columns) in body components
//   gravity, pivotRod, figureAxis[3], seconds (the clip's length at speed 1), name, legend strings
// Controls: play/pause (button or space), scrub (slider or arrow keys), speed, drag to turn the camera.
// URL hash: #frame=N starts paused at frame N; #paused starts paused at frame 0.
(function () {
  "use strict";
  var data = JSON.parse(document.getElementById("eulersym-data").textContent);
  var n = data.t.length;
  var canvas = document.getElementById("view");
  var ctx = canvas.getContext("2d");
  var playButton = document.getElementById("play");
  var scrub = document.getElementById("scrub");
  var speedBox = document.getElementById("speed");
  var clock = document.getElementById("clock");
  scrub.max = String(n - 1);

  var frame = 0, playing = true, speed = 1, azim = 35, elev = 18;
  var anchorTime = null, anchorFrame = 0;
  var stamps = null;

  var hash = window.location.hash.replace("#", "");
  hash.split("&").forEach(function (part) {
    var kv = part.split("=");
    if (kv[0] === "frame") { frame = Math.max(0, Math.min(n - 1, parseInt(kv[1], 10) || 0)); playing = false; }
    if (kv[0] === "paused") { playing = false; }
  });

  function basis() {
    var a = azim * Math.PI / 180, e = elev * Math.PI / 180;
    var towards = [Math.cos(e) * Math.cos(a), Math.cos(e) * Math.sin(a), Math.sin(e)];
    var right = [-Math.sin(a), Math.cos(a), 0];
    var up = [towards[1] * right[2] - towards[2] * right[1], towards[2] * right[0] - towards[0] * right[2],
              towards[0] * right[1] - towards[1] * right[0]];
    return [right, up, towards];
  }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function rotate(R, v) {
    return [R[0] * v[0] + R[1] * v[1] + R[2] * v[2], R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
            R[6] * v[0] + R[7] * v[1] + R[8] * v[2]];
  }

  function draw(i) {
    var W = canvas.width, H = canvas.height, s = Math.min(W, H) / 4.4, cx = W / 2, cy = H * 0.55;
    var B = basis();
    var light = [0, 0, 0];
    for (var k = 0; k < 3; k++) { light[k] = 0.3 * B[0][k] + 0.5 * B[1][k] + 0.6 * B[2][k]; }
    var ln = Math.sqrt(dot(light, light));
    light = [light[0] / ln, light[1] / ln, light[2] / ln];
    function screen(p) { return [cx + s * dot(p, B[0]), cy - s * dot(p, B[1])]; }
    function segment(a, b, colour, width) {
      var p = screen(a), q = screen(b);
      ctx.strokeStyle = colour; ctx.lineWidth = width;
      ctx.beginPath(); ctx.moveTo(p[0], p[1]); ctx.lineTo(q[0], q[1]); ctx.stroke();
    }
    function arrow(v, colour, label, side) {
      var p = screen([0, 0, 0]), q = screen(v), dx = q[0] - p[0], dy = q[1] - p[1];
      var len = Math.sqrt(dx * dx + dy * dy);
      if (len < 2) { return; }
      var ux = dx / len, uy = dy / len, head = Math.min(12, 0.3 * len);
      var bx = q[0] - head * ux, by = q[1] - head * uy;
      ctx.strokeStyle = colour; ctx.fillStyle = colour; ctx.lineWidth = 3;
      ctx.beginPath(); ctx.moveTo(p[0], p[1]); ctx.lineTo(bx, by); ctx.stroke();
      ctx.beginPath(); ctx.moveTo(q[0], q[1]);
      ctx.lineTo(bx - 0.45 * head * uy, by + 0.45 * head * ux); ctx.lineTo(bx + 0.45 * head * uy, by - 0.45 * head * ux);
      ctx.closePath(); ctx.fill();
      ctx.font = "bold 16px sans-serif";
      ctx.fillText(label, q[0] + 6 * ux + (side > 0 ? 6 : -16), q[1] + 6 * uy + 5);
    }

    ctx.fillStyle = "#ffffff"; ctx.fillRect(0, 0, W, H);
    var R = data.R[i];
    if (data.gravity) { segment([0, 0, -1.9], [0, 0, 1.9], "#dddddd", 1); }
    var body = data.vertices.map(function (v) { return rotate(R, v); });
    data.faces.forEach(function (f, j) {
      var a = body[f[0]], b = body[f[1]], c = body[f[2]];
      var u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]], w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
      var nrm = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
      var size = Math.sqrt(dot(nrm, nrm));
      if (size === 0 || dot(nrm, B[2]) <= 0) { return; }
      var f2 = 0.35 + 0.65 * Math.max(0, dot(nrm, light) / size), tint = data.tints[data.faceTint[j]];
      ctx.fillStyle = "rgb(" + Math.round(tint[0] * f2) + "," + Math.round(tint[1] * f2) + "," + Math.round(tint[2] * f2) + ")";
      ctx.strokeStyle = "#969696"; ctx.lineWidth = 1;
      ctx.beginPath();
      f.forEach(function (vi, m) { var p = screen(body[vi]); if (m === 0) { ctx.moveTo(p[0], p[1]); } else { ctx.lineTo(p[0], p[1]); } });
      ctx.closePath(); ctx.fill(); ctx.stroke();
    });
    ctx.strokeStyle = "#9467bd"; ctx.lineWidth = 2; ctx.beginPath();
    for (var m = 0; m <= i; m++) {
      var p = screen(data.trace[m]);
      if (m === 0) { ctx.moveTo(p[0], p[1]); } else { ctx.lineTo(p[0], p[1]); }
    }
    ctx.stroke();
    ["#c83c3c", "#289628", "#2850c8"].forEach(function (colour, j) {
      var e = rotate(R, [data.axes[0][j], data.axes[1][j], data.axes[2][j]]);
      segment([0, 0, 0], [1.25 * e[0], 1.25 * e[1], 1.25 * e[2]], colour, 1);
    });
    if (data.pivotRod) { segment([0, 0, 0], rotate(R, data.figureAxis), "#141414", 3); }
    if (data.gravity) {
      var o = screen([0, 0, 0]);
      ctx.fillStyle = "#141414"; ctx.beginPath(); ctx.arc(o[0], o[1], 3.5, 0, 2 * Math.PI); ctx.fill();
    }
    arrow(data.L[i], "#1f77b4", "L", -1);
    arrow(data.w[i], "#d62728", "\u03c9", 1);
    ctx.fillStyle = "#141414"; ctx.font = "16px sans-serif";
    ctx.fillText("t = " + data.t[i].toFixed(3) + " s", 10, 22);
    clock.textContent = "t = " + data.t[i].toFixed(3) + " s  (frame " + (i + 1) + " of " + n + ")";
    scrub.value = String(i);
  }

  function setFrame(i) { frame = ((i % n) + n) % n; anchorTime = null; draw(frame); }
  function play() { playing = true; anchorTime = null; playButton.textContent = "pause"; }
  function pause() { playing = false; playButton.textContent = "play"; }

  function tick(now) {
    if (stamps !== null) { stamps.push(now); }
    if (playing) {
      if (anchorTime === null) { anchorTime = now; anchorFrame = frame; }
      var step = (now - anchorTime) / 1000 * speed * (n - 1) / data.seconds;
      frame = (anchorFrame + Math.floor(step)) % n;
    }
    draw(frame);
    window.requestAnimationFrame(tick);
  }

  playButton.addEventListener("click", function () { if (playing) { pause(); } else { play(); } });
  scrub.addEventListener("input", function () { pause(); setFrame(parseInt(scrub.value, 10)); });
  speedBox.addEventListener("change", function () { speed = parseFloat(speedBox.value); anchorTime = null; });
  document.addEventListener("keydown", function (event) {
    if (event.key === " ") { if (playing) { pause(); } else { play(); } event.preventDefault(); }
    if (event.key === "ArrowRight") { pause(); setFrame(frame + 1); }
    if (event.key === "ArrowLeft") { pause(); setFrame(frame - 1); }
  });
  var drag = null;
  canvas.addEventListener("pointerdown", function (event) { drag = [event.clientX, event.clientY, azim, elev]; canvas.setPointerCapture(event.pointerId); });
  canvas.addEventListener("pointermove", function (event) {
    if (drag === null) { return; }
    azim = drag[2] - (event.clientX - drag[0]) * 0.5;
    elev = Math.max(-89, Math.min(89, drag[3] + (event.clientY - drag[1]) * 0.5));
    if (!playing) { draw(frame); }
  });
  canvas.addEventListener("pointerup", function () { drag = null; });

  // For tests and benchmarks: the frame shown, and the frame rate measured from requestAnimationFrame's own timestamps.
  window.eulersym = {
    frames: n,
    frame: function () { return frame; },
    setFrame: function (i) { pause(); setFrame(i); },
    play: play,
    pause: pause,
    turn: function (a, e) { azim = a; elev = e; draw(frame); },
    measure: function (ms) {
      play();
      stamps = [];
      return new Promise(function (resolve) {
        window.setTimeout(function () {
          var s = stamps; stamps = null;
          var fps = s.length > 1 ? (s.length - 1) * 1000 / (s[s.length - 1] - s[0]) : 0;
          resolve({ fps: fps, frames: s.length, first: s[0], last: s[s.length - 1] });
        }, ms);
      });
    }
  };
  playButton.textContent = playing ? "pause" : "play";
  draw(frame);
  window.requestAnimationFrame(tick);
})();
