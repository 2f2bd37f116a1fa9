// DeformLab's feedback viewer: two meshes side by side on canvas 2D, one camera for both.
// It reads only the numbers the grader wrote in each view's <script type="application/json"> block
// (grader/pipeline/feedback_view.py) and makes no request of any kind.
(function () {
  "use strict";

  function colourAt(stops, t) {
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    for (var i = 1; i < stops.length; i++) {
      var a = stops[i - 1], b = stops[i];
      if (t <= b[0]) {
        var u = b[0] > a[0] ? (t - a[0]) / (b[0] - a[0]) : 0;
        return [a[1] + u * (b[1] - a[1]), a[2] + u * (b[2] - a[2]), a[3] + u * (b[3] - a[3])];
      }
    }
    var last = stops[stops.length - 1];
    return [last[1], last[2], last[3]];
  }

  function setUp(root) {
    var data = JSON.parse(root.querySelector("script.dl-data").textContent);
    var canvases = Array.prototype.slice.call(root.querySelectorAll("canvas.dl-pane"));
    var select = root.querySelector("select.dl-field");
    var legends = root.querySelectorAll(".dl-legend");
    var d = data.d, faces = data.f, nf = faces.length / 3;
    var start = d === 3 ? { yaw: 0.6, pitch: 0.45, zoom: 1 } : { yaw: 0, pitch: 0, zoom: 1 };
    var cam = { yaw: start.yaw, pitch: start.pitch, zoom: start.zoom };
    var field = 0, pending = false;

    // Points in the camera's frame, x right, y up, z towards the viewer (orthographic).
    function turned(p) {
      var n = p.length / d, out = new Float64Array(3 * n);
      var cy = Math.cos(cam.yaw), sy = Math.sin(cam.yaw), cp = Math.cos(cam.pitch), sp = Math.sin(cam.pitch);
      for (var i = 0; i < n; i++) {
        var x = p[d * i] / data.q, y = p[d * i + 1] / data.q, z = d === 3 ? p[d * i + 2] / data.q : 0;
        var x1 = cy * x + sy * z, z1 = -sy * x + cy * z;
        out[3 * i] = x1;
        out[3 * i + 1] = cp * y - sp * z1;
        out[3 * i + 2] = sp * y + cp * z1;
      }
      return out;
    }

    function draw(k) {
      var canvas = canvases[k], ctx = canvas.getContext("2d");
      var ratio = window.devicePixelRatio || 1;
      var w = Math.max(1, Math.round(canvas.clientWidth * ratio)), h = Math.max(1, Math.round(canvas.clientHeight * ratio));
      if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
      ctx.fillStyle = "#fff";
      ctx.fillRect(0, 0, w, h);
      var P = turned(data.p[k]), levels = data.c[field][k], stops = data.m[field];
      var scale = 0.45 * Math.min(w, h) * cam.zoom / (d === 3 ? 1.35 : 1);  // the reference fits [-1, 1]^d
      var sx = function (i) { return w / 2 + scale * P[3 * i]; };
      var sy = function (i) { return h / 2 - scale * P[3 * i + 1]; };
      var order = new Array(nf);
      for (var t = 0; t < nf; t++) order[t] = t;
      var depth = new Float64Array(nf);
      for (t = 0; t < nf; t++) depth[t] = P[3 * faces[3 * t] + 2] + P[3 * faces[3 * t + 1] + 2] + P[3 * faces[3 * t + 2] + 2];
      order.sort(function (a, b) { return depth[a] - depth[b]; });  // far first: the painter's algorithm
      var edges = nf <= 4000;
      ctx.lineJoin = "round";
      for (var o = 0; o < nf; o++) {
        t = order[o];
        var i = faces[3 * t], j = faces[3 * t + 1], l = faces[3 * t + 2];
        var c = colourAt(stops, (levels[i] + levels[j] + levels[l]) / (3 * data.l));
        var shade = 1;
        if (d === 3) {
          var ax = P[3 * j] - P[3 * i], ay = P[3 * j + 1] - P[3 * i + 1], az = P[3 * j + 2] - P[3 * i + 2];
          var bx = P[3 * l] - P[3 * i], by = P[3 * l + 1] - P[3 * i + 1], bz = P[3 * l + 2] - P[3 * i + 2];
          var nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
          var len = Math.sqrt(nx * nx + ny * ny + nz * nz) || 1;
          shade = 0.45 + 0.55 * Math.abs(nz / len);
        }
        var fill = "rgb(" + Math.round(c[0] * shade) + "," + Math.round(c[1] * shade) + "," + Math.round(c[2] * shade) + ")";
        ctx.beginPath();
        ctx.moveTo(sx(i), sy(i));
        ctx.lineTo(sx(j), sy(j));
        ctx.lineTo(sx(l), sy(l));
        ctx.closePath();
        ctx.fillStyle = fill;
        ctx.fill();
        ctx.strokeStyle = edges ? "rgba(40,40,40,0.35)" : fill;
        ctx.lineWidth = 0.6 * ratio;
        ctx.stroke();
      }
      // The vertex of the largest difference: a ring.
      if (data.w >= 0) {
        ctx.beginPath();
        ctx.arc(sx(data.w), sy(data.w), 7 * ratio, 0, 2 * Math.PI);
        ctx.lineWidth = 2 * ratio;
        ctx.strokeStyle = "#c0008a";
        ctx.stroke();
      }
      // Handles: dots, numbered from 1 at each handle's mean position.
      ctx.font = "bold " + Math.round(13 * ratio) + "px system-ui, sans-serif";
      ctx.textAlign = "center";
      ctx.textBaseline = "middle";
      data.h.forEach(function (group, g) {
        var mx = 0, my = 0;
        group.forEach(function (v) {
          ctx.beginPath();
          ctx.arc(sx(v), sy(v), 3.5 * ratio, 0, 2 * Math.PI);
          ctx.fillStyle = "#111";
          ctx.fill();
          ctx.lineWidth = 1.2 * ratio;
          ctx.strokeStyle = "#fff";
          ctx.stroke();
          mx += sx(v); my += sy(v);
        });
        if (!group.length) return;
        mx /= group.length; my /= group.length;
        ctx.lineWidth = 3 * ratio;
        ctx.strokeStyle = "#fff";
        ctx.strokeText(String(g + 1), mx + 9 * ratio, my - 9 * ratio);
        ctx.fillStyle = "#111";
        ctx.fillText(String(g + 1), mx + 9 * ratio, my - 9 * ratio);
      });
      canvas.setAttribute("data-camera", [cam.yaw.toFixed(4), cam.pitch.toFixed(4), cam.zoom.toFixed(4)].join(" "));
    }

    function redraw() {
      if (pending) return;
      pending = true;
      window.requestAnimationFrame(function () {
        pending = false;
        draw(0);
        draw(1);
      });
    }

    function turn(dx, dy) {
      cam.yaw += dx;
      cam.pitch = Math.max(-1.55, Math.min(1.55, cam.pitch + dy));
      redraw();
    }

    function zoom(factor) {
      cam.zoom = Math.max(0.2, Math.min(40, cam.zoom * factor));
      redraw();
    }

    canvases.forEach(function (canvas) {
      var last = null;
      canvas.addEventListener("pointerdown", function (e) {
        last = [e.clientX, e.clientY];
        canvas.setPointerCapture(e.pointerId);
        e.preventDefault();
      });
      canvas.addEventListener("pointermove", function (e) {
        if (!last) return;
        turn((e.clientX - last[0]) * 0.01, (e.clientY - last[1]) * 0.01);
        last = [e.clientX, e.clientY];
      });
      var release = function () { last = null; };
      canvas.addEventListener("pointerup", release);
      canvas.addEventListener("pointercancel", release);
      canvas.addEventListener("wheel", function (e) {
        e.preventDefault();
        zoom(Math.exp(-e.deltaY * 0.0015));
      }, { passive: false });
      canvas.addEventListener("keydown", function (e) {
        var keys = { ArrowLeft: [-0.1, 0], ArrowRight: [0.1, 0], ArrowUp: [0, -0.1], ArrowDown: [0, 0.1] };
        if (keys[e.key]) { turn(keys[e.key][0], keys[e.key][1]); e.preventDefault(); }
        else if (e.key === "+" || e.key === "=") { zoom(1.2); e.preventDefault(); }
        else if (e.key === "-") { zoom(1 / 1.2); e.preventDefault(); }
      });
    });
    if (select) {
      select.addEventListener("change", function () {
        field = Math.max(0, Math.min(data.c.length - 1, parseInt(select.value, 10) || 0));
        for (var k = 0; k < legends.length; k++) legends[k].hidden = k !== field;
        redraw();
      });
    }
    var reset = root.querySelector("button.dl-reset");
    if (reset) {
      reset.addEventListener("click", function () {
        cam.yaw = start.yaw; cam.pitch = start.pitch; cam.zoom = start.zoom;
        redraw();
      });
    }
    window.addEventListener("resize", redraw);
    root.querySelector(".dl-interactive").hidden = false;
    redraw();
  }

  var roots = document.querySelectorAll("section.dl-view");
  for (var r = 0; r < roots.length; r++) {
    if (roots[r].querySelector("script.dl-data")) setUp(roots[r]);
  }
})();
