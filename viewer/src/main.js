// nmdp view: replays the runs of the page's payload (payload.js) in three.js, with a time slider,
// play/pause, speed, follow camera, toggles (lil-gui) and a time-synced plot panel (uPlot).
// The contract the tests rely on (title, #nmdp-view-warnings, input#nmdp-view-time, window.nmdpView,
// hash parameters) is in viewer/README.md.
import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import GUI from "lil-gui";
import uplotCss from "uplot/dist/uPlot.min.css";
import viewCss from "./style.css";
import { readPayload, frameAt } from "./payload.js";
import { buildRobot } from "./robot.js";
import { buildTerrain } from "./terrain.js";
import { buildContacts, buildPath } from "./contacts.js";
import { PlotPanel } from "./plots.js";
import { parseHash } from "./hash.js";

// Run 0 in its own colours; overlaid runs k > 0 tinted and translucent.
// Run 0's tint colours its path, legend swatch and plot lines; its robot keeps the URDF's colours and
// its force arrows are red, a colour no tint uses.
const RUN_TINTS = ["#1c7ed6", "#2f9e44", "#7048e8", "#f59f00", "#0c8599", "#d6336c"];
const OVERLAY_OPACITY = 0.45;
const SPEEDS = [0.1, 0.25, 0.5, 1, 2, 4];

function element(tag, props = {}, parent = null) {
  const e = Object.assign(document.createElement(tag), props);
  if (parent) parent.append(e);
  return e;
}

function injectStyles() {
  element("style", { textContent: uplotCss + "\n" + viewCss }, document.head);
}

function showError(message) {
  document.title = `nmdp view: error (${message})`;
  const box = document.getElementById("nmdp-view-error") || element("div", { id: "nmdp-view-error" }, document.body);
  box.textContent = `nmdp view cannot show this page: ${message}`;
}

function smallestStep(runs) {
  let step = Infinity;
  for (const run of runs) {
    for (let i = 1; i < run.frames; i++) step = Math.min(step, run.time[i] - run.time[i - 1]);
  }
  return Number.isFinite(step) && step > 0 ? step : 0.001;
}

class Viewer {
  constructor(payload, options) {
    this.payload = payload;
    this.runs = payload.runs;
    this.options = options;
    this.time = 0;
    this.rendered = 0;
    this.playing = false;
    this.settings = {
      speed: 1, follow: options.follow, forces: true, path: true, terrain: true,
      newtonsPerMetre: 200, runs: this.runs.map(() => true),
    };
    this.endTime = Math.max(...this.runs.map((r) => r.time[r.frames - 1]));
    this.startTime = Math.min(...this.runs.map((r) => r.time[0]));
    this.warnings = [...payload.warnings, ...this.runs.flatMap((r) => r.warnings)];
    this.layout();
    this.buildScene();
    this.buildControls();
    this.lastBase = this.basePosition(0);
  }

  layout() {
    if (!this.options.panel) document.body.classList.add("nmdp-view-nopanel");
    this.stage = element("div", { id: "nmdp-view-stage" }, document.body);
    this.panel = element("div", { id: "nmdp-view-panel" }, document.body);
    this.warningList = element("ul", { id: "nmdp-view-warnings" }, this.panel);
    this.legend = element("ul", { id: "nmdp-view-legend" }, this.stage);
    this.runs.forEach((run, k) => {
      const li = element("li", { title: `${run.file}\nstatus: ${run.status}` }, this.legend);
      const swatch = element("span", { className: "swatch" }, li);
      swatch.style.background = RUN_TINTS[k % RUN_TINTS.length];
      if (k > 0) swatch.style.opacity = String(OVERLAY_OPACITY + 0.2);
      li.append(run.label + (run.status && run.status !== "complete" ? ` (${run.status})` : ""));
    });
  }

  showWarnings() {
    this.warningList.replaceChildren(...this.warnings.map((w) => element("li", { textContent: w })));
    // With the panel hidden the warnings stay visible above the canvas.
    if (!this.options.panel && this.warnings.length > 0) this.stage.append(this.warningList);
  }

  buildScene() {
    const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(window.devicePixelRatio);
    renderer.setClearColor(0xdde3ea);
    this.stage.prepend(renderer.domElement);
    this.renderer = renderer;
    const scene = new THREE.Scene();
    this.scene = scene;
    scene.add(new THREE.HemisphereLight(0xffffff, 0x606060, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(3, -4, 6);
    scene.add(sun);

    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 200);
    this.camera.up.set(0, 0, 1); // the world is z-up, as URDF
    const p0 = this.basePosition(0);
    this.camera.position.set(p0[0] + 0.9, p0[1] - 1.6, p0[2] + 0.8);
    this.controls = new OrbitControls(this.camera, renderer.domElement);
    this.controls.target.set(p0[0], p0[1], p0[2]);
    if (this.options.camera) this.setCamera(this.options.camera.slice(0, 3), this.options.camera.slice(3, 6));
    this.controls.addEventListener("change", () => this.requestRender());

    this.terrain = null;
    if (this.payload.terrain) {
      this.terrain = buildTerrain(this.payload.terrain).group;
      scene.add(this.terrain);
    }
    this.runViews = this.runs.map((run, k) => {
      const look = k === 0 ? { opacity: 1, tint: null }
        : { opacity: OVERLAY_OPACITY, tint: new THREE.Color(RUN_TINTS[k % RUN_TINTS.length]) };
      const robot = buildRobot(run, look, this.warnings);
      const contacts = buildContacts(run, look);
      const path = buildPath(run, look);
      scene.add(robot.group, contacts.group, path);
      return { run, robot, contacts, path };
    });
    window.addEventListener("resize", () => this.resize());
    this.resize();
  }

  buildControls() {
    const bar = element("div", { id: "nmdp-view-bar" }, this.stage);
    this.playButton = element("button", { type: "button", textContent: "play" }, bar);
    this.playButton.addEventListener("click", () => (this.playing ? this.pause() : this.play()));
    const slider = element("input", {
      id: "nmdp-view-time", type: "range", min: "0", max: String(this.endTime),
      step: String(smallestStep(this.runs)), value: "0",
    }, bar);
    slider.addEventListener("input", () => this.setTime(this.snapToFrame(Number(slider.value))));
    this.slider = slider;
    this.clock = element("span", { id: "nmdp-view-clock" }, bar);
    window.addEventListener("keydown", (e) => {
      if (e.key === " " && e.target === document.body) { e.preventDefault(); this.playing ? this.pause() : this.play(); }
    });

    const gui = new GUI({ title: "view", container: this.stage });
    gui.add(this.settings, "speed", SPEEDS).name("speed (×)");
    gui.add(this.settings, "follow").name("follow camera").listen().onChange(() => this.requestRender());
    gui.add(this.settings, "newtonsPerMetre", 10, 2000, 10).name("arrow N per m").onChange(() => this.update());
    gui.add(this.settings, "forces").name("forces").onChange(() => this.update());
    gui.add(this.settings, "path").name("path").onChange(() => this.update());
    if (this.terrain) gui.add(this.settings, "terrain").name("terrain").onChange(() => this.update());
    if (this.runs.length > 1) {
      const folder = gui.addFolder("runs");
      this.runs.forEach((run, k) => {
        const proxy = { get shown() { return this.owner.settings.runs[k]; }, set shown(v) { this.owner.settings.runs[k] = v; }, owner: this };
        folder.add(proxy, "shown").name(`${k + 1}: ${run.label}`.slice(0, 40)).onChange(() => this.update());
      });
    }
    // On a small window the controls would cover the robot: folded until opened.
    if (this.stage.clientWidth < 640) gui.close();
    this.gui = gui;

    this.plots = new PlotPanel(this.runs, this.runs.map((_, k) => RUN_TINTS[k % RUN_TINTS.length]),
      this.panel, () => this.time, (t) => this.setTime(t));
    element("div", { className: "nmdp-view-generator", textContent: this.payload.generator }, this.panel);
  }

  // The slider holds multiples of its step, which miss the stored times by rounding (20 × 0.05 is
  // 0.999..., the last time 1.0): a value within a millionth of a step of a frame's time is that time.
  snapToFrame(t) {
    const tolerance = 1e-6 * Number(this.slider.step);
    for (const run of this.runs) {
      const i = frameAt(run.time, t + tolerance);
      if (Math.abs(run.time[i] - t) <= tolerance) return run.time[i];
    }
    return t;
  }

  basePosition(frame, run = this.runs[0]) {
    const b = run.base.position;
    return [b[frame * 3], b[frame * 3 + 1], b[frame * 3 + 2]];
  }

  resize() {
    const w = Math.max(1, this.stage.clientWidth);
    const h = Math.max(1, this.stage.clientHeight);
    this.renderer.setSize(w, h, true);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    if (this.plots) this.plots.resize();
    this.requestRender();
  }

  // Poses every run at this.time, moves the follow camera with the first run's trunk, renders.
  update() {
    const t = this.time;
    this.runViews.forEach((view, k) => {
      const frame = frameAt(view.run.time, t);
      const shown = this.settings.runs[k];
      view.robot.setFrame(frame);
      view.contacts.setFrame(frame, this.settings.newtonsPerMetre, this.settings.forces);
      view.robot.group.visible = shown;
      view.contacts.group.visible = shown;
      view.path.visible = shown && this.settings.path;
    });
    if (this.terrain) this.terrain.visible = this.settings.terrain;
    const base = this.basePosition(frameAt(this.runs[0].time, t));
    if (this.settings.follow) {
      // Keep the camera's offset from the trunk: the view travels with the robot.
      const shift = new THREE.Vector3(base[0] - this.lastBase[0], base[1] - this.lastBase[1], base[2] - this.lastBase[2]);
      this.camera.position.add(shift);
      this.controls.target.add(shift);
      this.controls.update();
    }
    this.lastBase = base;
    this.slider.value = String(t);
    this.clock.textContent = `${t.toFixed(3)} s`;
    this.plots.redraw();
    this.render();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
    this.rendered += 1;
  }

  requestRender() {
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame(() => { this.renderPending = false; this.render(); });
  }

  setTime(t) {
    const clamped = Math.min(Math.max(Number(t) || 0, 0), this.endTime);
    this.time = clamped;
    this.update();
    return new Promise((resolve) => requestAnimationFrame(() => resolve(this.time)));
  }

  play() {
    if (this.playing) return;
    if (this.time >= this.endTime) this.time = this.startTime;
    this.playing = true;
    this.playButton.textContent = "pause";
    let last = performance.now();
    const step = (now) => {
      if (!this.playing) return;
      const dt = (now - last) / 1000;
      last = now;
      this.time = Math.min(this.endTime, this.time + dt * this.settings.speed);
      this.update();
      if (this.time >= this.endTime) { this.pause(); return; }
      requestAnimationFrame(step);
    };
    requestAnimationFrame(step);
  }

  pause() {
    this.playing = false;
    this.playButton.textContent = "play";
  }

  setCamera(position, target) {
    this.camera.position.set(...position);
    this.controls.target.set(...target);
    this.controls.update();
    this.requestRender();
  }

  project(point) {
    const v = new THREE.Vector3(...point).project(this.camera);
    const canvas = this.renderer.domElement;
    return [(v.x + 1) / 2 * canvas.clientWidth, (1 - v.y) / 2 * canvas.clientHeight];
  }
}

function boot() {
  document.title = "nmdp view: loading";
  injectStyles();
  let viewer;
  try {
    const payload = readPayload(document);
    viewer = new Viewer(payload, parseHash(location.hash));
    viewer.showWarnings();
    viewer.time = Math.min(Math.max(viewer.options.t ?? 0, 0), viewer.endTime);
    // A camera from the hash is where it is at that time: the follow camera moves on from there.
    if (viewer.options.camera) viewer.lastBase = viewer.basePosition(frameAt(viewer.runs[0].time, viewer.time));
    viewer.update();
  } catch (e) {
    console.error(e);
    showError(e.message || String(e));
    return;
  }
  window.nmdpView = {
    get frames() { return viewer.runs[0].frames; },
    get time() { return viewer.time; },
    get rendered() { return viewer.rendered; },
    setTime: (t) => viewer.setTime(t),
    play: () => viewer.play(),
    pause: () => viewer.pause(),
    setFollow: (on) => { viewer.settings.follow = Boolean(on); },
    setCamera: (position, target) => viewer.setCamera(position, target),
    project: (point) => viewer.project(point),
  };
  // The first frame is drawn (update() rendered it); say so after the browser has composited it.
  requestAnimationFrame(() => { document.title = `nmdp view: ready (${viewer.runs[0].frames} frames)`; });
}

if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", boot);
else boot();
