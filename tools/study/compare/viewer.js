// The comparison page's viewer (compare.html, docs/studies.md, "The
// comparison page"): one canvas shows the reference or a row's render, its
// false-colour error map or its HDR-FLIP map, at a zoom and pan that every
// image shares, so that flipping between rows compares the same pixels.
//
// Data arrive as scripts (a page opened from file:// may not fetch files):
// compare/manifest.js calls nuldCompare.load(manifest), and each image's
// file, added as a script tag when first shown, calls nuldCompare.image(key,
// data) with the render as RGBE bytes (base64) and its maps as PNG data URIs.
"use strict";

const nuldCompare = (() => {
  const state = { scene: 0, spp: 0, row: 0, mode: "image", exposure: 0, zoom: 1, panX: 0,
    panY: 0, ready: false };
  let manifest = null;
  const images = new Map();   // key -> decoded image {width, height, linear, error, flip}
  const waiting = new Map();  // key -> [callbacks]
  const shown = { key: "", mode: "", exposure: NaN, canvas: null };  // the drawn raster
  const $ = (id) => document.getElementById(id);
  const canvas = () => $("canvas");

  // RGBE (Ward's shared exponent): channel c = (byte + 0.5) * 2^(e - 136).
  function decodeRgbe(base64, width, height) {
    const bytes = Uint8Array.from(atob(base64), (c) => c.charCodeAt(0));
    if (bytes.length !== 4 * width * height) throw new Error("RGBE data of the wrong size");
    const linear = new Float32Array(3 * width * height);
    for (let i = 0, o = 0; i < bytes.length; i += 4, o += 3) {
      const e = bytes[i + 3];
      if (e === 0) continue;
      const f = Math.pow(2, e - 136);
      linear[o] = (bytes[i] + 0.5) * f;
      linear[o + 1] = (bytes[i + 1] + 0.5) * f;
      linear[o + 2] = (bytes[i + 2] + 0.5) * f;
    }
    return linear;
  }

  function toSrgb(v) {
    const c = v <= 0 ? 0 : v >= 1 ? 1 : v <= 0.0031308 ? 12.92 * v
      : 1.055 * Math.pow(v, 1 / 2.4) - 0.055;
    return Math.round(255 * c);
  }

  function pictureOf(dataUri, done) {
    if (!dataUri) return done(null);
    const img = new Image();
    img.onload = () => done(img);
    img.onerror = () => done(null);
    img.src = dataUri;
  }

  // Called by an image's data file.
  function image(key, data) {
    const entry = { width: data.width, height: data.height,
      linear: decodeRgbe(data.rgbe, data.width, data.height), error: null, flip: null };
    let pending = 2;
    const finish = () => {
      if (--pending > 0) return;
      images.set(key, entry);
      for (const callback of waiting.get(key) || []) callback(entry);
      waiting.delete(key);
    };
    pictureOf(data.error, (img) => { entry.error = img; finish(); });
    pictureOf(data.flip, (img) => { entry.flip = img; finish(); });
  }

  function withImage(key, callback) {
    if (images.has(key)) return callback(images.get(key));
    if (waiting.has(key)) return waiting.get(key).push(callback);
    waiting.set(key, [callback]);
    const script = document.createElement("script");
    script.src = "compare/" + key;
    script.onerror = () => status(key + ": could not load (rerun nuld study report)");
    document.body.appendChild(script);
  }

  const sceneOf = () => manifest.scenes[state.scene];
  const rowsOf = () => [{ label: "reference", data: sceneOf().reference, reference: true }]
    .concat(sceneOf().spps[state.spp].rows);
  const currentRow = () => rowsOf()[state.row];

  // The raster of the current image in the current mode and exposure, at
  // the image's own resolution (the view scales it without smoothing).
  function raster(entry, key) {
    const mode = currentRow().reference ? "image" : state.mode;
    if (shown.key === key && shown.mode === mode && shown.exposure === state.exposure)
      return shown.canvas;
    const c = document.createElement("canvas");
    c.width = entry.width;
    c.height = entry.height;
    const ctx = c.getContext("2d");
    if (mode === "image") {
      const out = ctx.createImageData(entry.width, entry.height);
      const scale = Math.pow(2, state.exposure);
      for (let p = 0, o = 0; o < out.data.length; p += 3, o += 4) {
        out.data[o] = toSrgb(scale * entry.linear[p]);
        out.data[o + 1] = toSrgb(scale * entry.linear[p + 1]);
        out.data[o + 2] = toSrgb(scale * entry.linear[p + 2]);
        out.data[o + 3] = 255;
      }
      ctx.putImageData(out, 0, 0);
    } else if (entry[mode]) {
      ctx.drawImage(entry[mode], 0, 0, entry.width, entry.height);
    }
    Object.assign(shown, { key, mode, exposure: state.exposure, canvas: c });
    return c;
  }

  function draw() {
    const view = canvas(), key = currentRow().data;
    view.width = view.clientWidth;
    view.height = view.clientHeight;
    state.ready = false;
    withImage(key, (entry) => {
      if (currentRow().data !== key) return;  // switched again while it loaded
      const ctx = view.getContext("2d");
      ctx.setTransform(1, 0, 0, 1, 0, 0);
      ctx.fillStyle = "#111";
      ctx.fillRect(0, 0, view.width, view.height);
      ctx.imageSmoothingEnabled = false;
      ctx.setTransform(state.zoom, 0, 0, state.zoom, state.panX, state.panY);
      ctx.drawImage(raster(entry, key), 0, 0);
      state.ready = true;
      describe();
    });
  }

  function status(text) { $("status").textContent = text; }

  function describe(pixel) {
    const row = currentRow(), s = sceneOf();
    const number = (v, e) => (Number.isFinite(v) ? v.toExponential(4) : "-") +
      (Number.isFinite(e) ? " +- " + e.toExponential(2) : "");
    let text = `${s.scene} (${s.integrator}), ${s.spps[state.spp].spp} spp: ${row.label}`;
    if (!row.reference) {
      text += `  mode ${state.mode}  mse ${number(row.mse, row.mseStderr)}`;
      text += `  flip ${number(row.flip, row.flipStderr)}`;
    }
    text += `  zoom ${state.zoom}x  exposure ${state.exposure >= 0 ? "+" : ""}` +
      state.exposure.toFixed(1);
    if (pixel) text += `  pixel ${pixel}`;
    status(text);
  }

  // The view: 1:1 and centred ("h"), zoom about a canvas point, pan.
  function home() {
    const s = sceneOf(), view = canvas();
    state.zoom = 1;
    state.panX = Math.round((view.clientWidth - s.width) / 2);
    state.panY = Math.round((view.clientHeight - s.height) / 2);
  }
  // The largest power-of-two zoom at which the image fits the view ("z"),
  // centred: a small study's renders at a readable size.
  function fit() {
    const s = sceneOf(), view = canvas();
    let zoom = 1;
    while (zoom < 64 && s.width * zoom * 2 <= view.clientWidth &&
           s.height * zoom * 2 <= view.clientHeight) zoom *= 2;
    state.zoom = zoom;
    state.panX = Math.round((view.clientWidth - zoom * s.width) / 2);
    state.panY = Math.round((view.clientHeight - zoom * s.height) / 2);
  }
  function zoomAbout(factor, cx, cy) {
    const zoom = Math.min(64, Math.max(1 / 8, state.zoom * factor));
    // The image point under (cx, cy) stays there.
    state.panX = Math.round(cx - (cx - state.panX) * zoom / state.zoom);
    state.panY = Math.round(cy - (cy - state.panY) * zoom / state.zoom);
    state.zoom = zoom;
    draw();
  }
  function setExposure(stops) {
    state.exposure = Math.min(10, Math.max(-10, stops));
    $("exposure").value = state.exposure;
    $("exposure-value").textContent = (state.exposure >= 0 ? "+" : "") +
      state.exposure.toFixed(1);
    draw();
  }
  // A map's key pressed again goes back to the image.
  function setMode(mode) {
    state.mode = state.mode === mode && mode !== "image" ? "image" : mode;
    markMode();
    draw();
  }
  function markMode() {
    for (const b of document.querySelectorAll("#modes button"))
      b.classList.toggle("current", b.dataset.mode === state.mode);
  }
  function setRow(i) {
    const n = rowsOf().length;
    state.row = ((i % n) + n) % n;
    const buttons = document.querySelectorAll("#rows button");
    buttons.forEach((b, k) => b.classList.toggle("current", k === state.row));
    draw();
  }
  function setSpp(i) {
    const n = sceneOf().spps.length;
    state.spp = Math.min(n - 1, Math.max(0, i));
    $("spp").value = String(state.spp);
    const keep = currentRowLabel();
    fillRows();
    setRow(Math.max(0, rowsOf().findIndex((r) => r.label === keep)));
  }
  const currentRowLabel = () => (rowsOf()[state.row] || {}).label;
  function setScene(i) {
    state.scene = i;
    $("scene").value = String(i);
    const spp = $("spp");
    spp.innerHTML = "";
    sceneOf().spps.forEach((s, k) => spp.add(new Option(String(s.spp), String(k))));
    state.spp = 0;
    fillRows();
    home();
    setRow(0);
  }
  function fillRows() {
    const nav = $("rows");
    nav.innerHTML = "";
    rowsOf().forEach((row, k) => {
      const b = document.createElement("button");
      if (k < 10) b.innerHTML = `<span class="key">${k}</span>`;
      b.appendChild(document.createTextNode(row.label));
      b.addEventListener("click", () => setRow(k));
      nav.appendChild(b);
    });
  }

  function onKey(event) {
    if (event.target.tagName === "SELECT" || event.target.tagName === "INPUT") return;
    const view = canvas(), cx = view.clientWidth / 2, cy = view.clientHeight / 2;
    const k = event.key;
    if (k >= "0" && k <= "9") setRow(Number(k));
    else if (k === "ArrowRight" || k === "ArrowDown") setRow(state.row + 1);
    else if (k === "ArrowLeft" || k === "ArrowUp") setRow(state.row - 1);
    else if (k === "i") setMode("image");
    else if (k === "e") setMode("error");
    else if (k === "f") setMode("flip");
    else if (k === "+" || k === "=") zoomAbout(2, cx, cy);
    else if (k === "-") zoomAbout(0.5, cx, cy);
    else if (k === "h") { home(); draw(); }
    else if (k === "z") { fit(); draw(); }
    else if (k === "]") setExposure(state.exposure + 0.5);
    else if (k === "[") setExposure(state.exposure - 0.5);
    else if (k === "PageDown") setSpp(state.spp + 1);
    else if (k === "PageUp") setSpp(state.spp - 1);
    else return;
    event.preventDefault();
  }

  function listen() {
    const view = canvas();
    document.addEventListener("keydown", onKey);
    $("scene").addEventListener("change", (e) => setScene(Number(e.target.value)));
    $("spp").addEventListener("change", (e) => setSpp(Number(e.target.value)));
    $("exposure").addEventListener("input", (e) => setExposure(Number(e.target.value)));
    for (const b of document.querySelectorAll("#modes button"))
      b.addEventListener("click", () => setMode(b.dataset.mode));
    view.addEventListener("wheel", (e) => {
      e.preventDefault();
      const r = view.getBoundingClientRect();
      zoomAbout(e.deltaY < 0 ? 2 : 0.5, e.clientX - r.left, e.clientY - r.top);
    }, { passive: false });
    let drag = null;
    view.addEventListener("mousedown", (e) => {
      drag = { x: e.clientX, y: e.clientY, panX: state.panX, panY: state.panY };
      view.classList.add("dragging");
    });
    window.addEventListener("mouseup", () => { drag = null; view.classList.remove("dragging"); });
    view.addEventListener("mousemove", (e) => {
      if (drag) {
        state.panX = drag.panX + e.clientX - drag.x;
        state.panY = drag.panY + e.clientY - drag.y;
        draw();
        return;
      }
      const entry = images.get(currentRow().data);
      if (!entry) return;
      const r = view.getBoundingClientRect();
      const x = Math.floor((e.clientX - r.left - state.panX) / state.zoom),
        y = Math.floor((e.clientY - r.top - state.panY) / state.zoom);
      if (x < 0 || y < 0 || x >= entry.width || y >= entry.height) return describe();
      const p = 3 * (y * entry.width + x), v = entry.linear;
      describe(`(${x}, ${y}) rgb ${v[p].toPrecision(4)} ${v[p + 1].toPrecision(4)} ` +
        v[p + 2].toPrecision(4));
    });
    window.addEventListener("resize", draw);
  }

  // Called by compare/manifest.js.
  function load(m) {
    manifest = m;
    document.title = m.title;
    const scene = $("scene");
    m.scenes.forEach((s, k) => scene.add(new Option(`${s.scene} (${s.integrator})`, String(k))));
    listen();
    markMode();
    setScene(0);
  }

  // What the page's test reads: the view's state and where an image pixel
  // lands on the canvas.
  return { load, image, state: () => Object.assign({}, state, { rows: rowsOf().map((r) => r.label) }) };
})();
