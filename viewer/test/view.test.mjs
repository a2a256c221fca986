// Browser tests of the page `nmdp view` writes: headless Debian chromium (test/browser.mjs) opens pages
// made from short runs of the quadruped and checks the contract of viewer/README.md: the "ready"
// title, the robot drawn where the run says (pixels around nmdpView.project of the trunk position),
// scrubbing with the slider, warnings for a run without its URDF and for a killed run, two runs overlaid.
// Run by ctest (viewer.browser) with NMDP_BINARY and NMDP_SOURCE_DIR set, or by `npm test` in viewer/.
import { describe, it, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync, spawn } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";

const viewerDir = path.dirname(path.dirname(fileURLToPath(import.meta.url)));
const sourceDir = process.env.NMDP_SOURCE_DIR || path.dirname(viewerDir);
const nmdp = process.env.NMDP_BINARY || path.join(sourceDir, "build", "nmdp");
const scene = path.join(sourceDir, "models", "scenes", "quadruped_trot_sand3d.json");
// The pages embed this checkout's bundle, whatever NMDP_VIEWER_BUNDLE the caller has set.
const bundle = path.join(viewerDir, "dist", "nmdp-view.js");

// Missing pieces fail every test with one message saying what to do: never a silent skip.
function missingPrerequisites() {
  const problems = [];
  if (!fs.existsSync(path.join(viewerDir, "node_modules", "playwright-core"))) {
    problems.push(`${viewerDir}/node_modules is missing: run scripts/build.sh (or npm ci in viewer/)`);
  }
  if (!fs.existsSync(bundle)) {
    problems.push(`${viewerDir}/dist/nmdp-view.js is missing: run scripts/build.sh (or npm run build in viewer/)`);
  }
  const chromium = process.env.NMDP_CHROMIUM || "/usr/bin/chromium";
  if (!fs.existsSync(chromium)) problems.push(`${chromium} is missing: run scripts/install-deps.sh (Debian's chromium)`);
  if (!fs.existsSync(nmdp)) problems.push(`${nmdp} (NMDP_BINARY) is missing: build nmdp`);
  return problems;
}

function simulate(out, ...settings) {
  execFileSync(nmdp, ["simulate", scene, "--quiet", ...settings.flatMap((s) => ["--set", s]), "--out", out],
    { stdio: ["ignore", "ignore", "inherit"] });
}

function view(out, ...runs) {
  execFileSync(nmdp, ["view", ...runs, "--out", out],
    { stdio: ["ignore", "ignore", "pipe"], env: { ...process.env, NMDP_VIEWER_BUNDLE: bundle } });
}

// The payload of a page, with base positions and times decoded.
function readPayload(file) {
  const html = fs.readFileSync(file, "utf8");
  const start = html.indexOf(">", html.indexOf('id="nmdp-view-data"')) + 1;
  const payload = JSON.parse(html.slice(start, html.indexOf("</script>", start)));
  const decode = (a) => {
    const bytes = Buffer.from(a.b64, "base64");
    const Type = { float32: Float32Array, float64: Float64Array, uint8: Uint8Array }[a.dtype];
    return new Type(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength));
  };
  for (const run of payload.runs) {
    run.timeValues = decode(run.time);
    run.basePositions = decode(run.base.position);
  }
  return payload;
}

function basePosition(run, frame) {
  return Array.from(run.basePositions.subarray(frame * 3, frame * 3 + 3));
}

// Last frame with time <= t.
function frameAt(run, t) {
  let frame = 0;
  while (frame + 1 < run.frames && run.timeValues[frame + 1] <= t) frame++;
  return frame;
}

async function warningsOf(page) {
  return page.$$eval("#nmdp-view-warnings li", (items) => items.map((li) => li.textContent));
}

describe("nmdp view in headless chromium", () => {
  let tmp;
  let browser;
  let png;
  let openPage;
  let run;        // the 1 s trot
  let page1;      // its page

  before(async () => {
    const problems = missingPrerequisites();
    if (problems.length) throw new Error(`the browser test cannot run:\n  ${problems.join("\n  ")}`);
    const browserModule = await import("./browser.mjs");
    png = await import("./png.mjs");
    openPage = browserModule.openPage;
    tmp = fs.mkdtempSync(path.join(os.tmpdir(), "nmdp-view-test-"));
    simulate(path.join(tmp, "T.h5"), "duration=1");
    view(path.join(tmp, "T.html"), path.join(tmp, "T.h5"));
    page1 = path.join(tmp, "T.html");
    run = readPayload(page1).runs[0];
    browser = await browserModule.launchBrowser();
  });

  after(async () => {
    if (browser) await browser.close();
    if (tmp) fs.rmSync(tmp, { recursive: true, force: true });
  });

  it("says it is ready with the run's number of frames", async () => {
    // 1 s at dt = 50 ms: the initial state and 20 steps.
    assert.equal(run.frames, 21);
    assert.equal(run.timeValues.length, 21);
    assert.ok(Math.abs(run.timeValues[20] - 1) < 1e-9, `last time ${run.timeValues[20]}`);
    const page = await openPage(browser.context, page1);
    assert.equal(await page.title(), "nmdp view: ready (21 frames)");
    assert.deepEqual(page.nmdpErrors, []);
    assert.equal(await page.evaluate(() => window.nmdpView.frames), 21);
    assert.ok(await page.evaluate(() => window.nmdpView.rendered) >= 1);
    await page.close();
  });

  it("draws the robot where the run says, and scrubbing moves it", async (t) => {
    const early = run.timeValues[4];   // 0.2 s
    const late = run.timeValues[20];   // 1 s: the trunk is about 0.3 m further
    const start = basePosition(run, 0);
    // A fixed camera 2.2 m to the side of the walk, looking at its middle.
    const camera = [start[0] + 0.3, start[1] - 2.2, 0.9, start[0] + 0.2, start[1], 0.25];
    const hash = (t) => `t=${t}&follow=0&camera=${camera.join(",")}&panel=0`;

    const earlyPage = await openPage(browser.context, page1, hash(early));
    assert.match(await earlyPage.title(), /^nmdp view: ready/);
    const earlyShot = png.decodePng(await earlyPage.screenshot());
    // Not blank: a rendered scene has many colours and is not all one background.
    assert.ok(png.distinctColours(earlyShot) > 200, `${png.distinctColours(earlyShot)} distinct colours`);
    assert.ok(png.shareLikeCorner(earlyShot) < 0.8, `${png.shareLikeCorner(earlyShot)} of the pixels like the corner`);

    const lateFrame = frameAt(run, late);
    const earlyFrame = frameAt(run, early);
    const canvasOrigin = await earlyPage.evaluate(() => {
      const r = document.querySelector("canvas").getBoundingClientRect();
      return [r.left, r.top];
    });
    const project = async (page, point) => {
      const [x, y] = await page.evaluate((p) => window.nmdpView.project(p), point);
      return [x + canvasOrigin[0], y + canvasOrigin[1]];
    };
    const earlyPixel = await project(earlyPage, basePosition(run, earlyFrame));
    const latePixel = await project(earlyPage, basePosition(run, lateFrame));
    const apart = Math.hypot(earlyPixel[0] - latePixel[0], earlyPixel[1] - latePixel[1]);
    assert.ok(apart > 40, `the trunk moves only ${apart} px between ${early} s and ${late} s`);
    for (const p of [earlyPixel, latePixel]) {
      assert.ok(p[0] > 20 && p[0] < earlyShot.width - 20 && p[1] > 20 && p[1] < earlyShot.height - 20, `${p} is off the screen`);
    }

    const latePage = await openPage(browser.context, page1, hash(late));
    const lateShot = png.decodePng(await latePage.screenshot());
    await latePage.close();
    const radius = 12;
    // Where the run puts the trunk at 0.2 s, the 0.2 s picture differs from the 1 s one (the robot has
    // left), and so at the 1 s position; far from both (the top-left corner) nothing changes.
    const atEarly = png.regionDifference(earlyShot, lateShot, earlyPixel, radius);
    const atLate = png.regionDifference(earlyShot, lateShot, latePixel, radius);
    const corner = png.regionDifference(earlyShot, lateShot, [radius, radius], radius);
    t.diagnostic(`trunk ${apart.toFixed(0)} px apart; differences per channel: ${atEarly.toFixed(1)} at 0.2 s, ${atLate.toFixed(1)} at 1 s, ${corner.toFixed(1)} in the corner`);
    assert.ok(atEarly > 20, `around the 0.2 s trunk the pictures differ by ${atEarly} per channel`);
    assert.ok(atLate > 20, `around the 1 s trunk the pictures differ by ${atLate} per channel`);
    assert.ok(corner < 2, `the corner differs by ${corner} per channel`);

    // Scrub with the slider (an input event, as a user's drag) to 1 s.
    await earlyPage.evaluate(async (time) => {
      const slider = document.getElementById("nmdp-view-time");
      slider.value = String(time);
      slider.dispatchEvent(new Event("input"));
      await new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve)));
    }, late);
    const shownTime = await earlyPage.evaluate(() => window.nmdpView.time);
    assert.equal(frameAt(run, shownTime), lateFrame, `scrubbed to ${shownTime} s`);
    assert.match(await earlyPage.textContent("#nmdp-view-clock"), /^1\.000 s$/);
    const scrubbedShot = png.decodePng(await earlyPage.screenshot());
    // The scrubbed picture shows the robot at the 1 s position, as the page opened at 1 s does, and
    // no longer at the 0.2 s one.
    const scrubbedAtLate = png.regionDifference(scrubbedShot, lateShot, latePixel, radius);
    const scrubbedAtEarly = png.regionDifference(scrubbedShot, lateShot, earlyPixel, radius);
    t.diagnostic(`scrubbed against opened at 1 s: ${scrubbedAtLate.toFixed(1)}, ${scrubbedAtEarly.toFixed(1)}`);
    assert.ok(scrubbedAtLate < 3, `scrubbed and opened at 1 s differ by ${scrubbedAtLate} around the trunk`);
    assert.ok(scrubbedAtEarly < 3, `scrubbed and opened at 1 s differ by ${scrubbedAtEarly} at the 0.2 s trunk`);
    assert.ok(png.regionDifference(scrubbedShot, earlyShot, latePixel, radius) > 20, "scrubbing changed nothing at the 1 s trunk");
    await earlyPage.close();
  });

  it("follows the trunk by default, and plays", async () => {
    const page = await openPage(browser.context, page1);
    const projectAt = (time, frame) => page.evaluate(async ([t, p]) => {
      await window.nmdpView.setTime(t);
      return window.nmdpView.project(p);
    }, [time, basePosition(run, frame)]);
    // The follow camera moves with the trunk: it stays on the same pixel.
    const a = await projectAt(run.timeValues[4], 4);
    const b = await projectAt(run.timeValues[20], 20);
    assert.ok(Math.hypot(a[0] - b[0], a[1] - b[1]) < 0.5, `the followed trunk moved from ${a} to ${b}`);
    // Without it the camera stays and the trunk moves across the view.
    await page.evaluate(() => window.nmdpView.setFollow(false));
    const c = await projectAt(run.timeValues[4], 4);
    assert.ok(Math.hypot(b[0] - c[0], b[1] - c[1]) > 20, `the unfollowed trunk stayed at ${b} / ${c}`);
    // play() advances the time and draws; pause() stops it. SwiftShader on a busy machine may draw
    // a frame a second only (and one late frame may reach the end): wait for one, however long.
    const [startTime, startDrawn] = await page.evaluate(() => [window.nmdpView.time, window.nmdpView.rendered]);
    await page.evaluate(() => window.nmdpView.play());
    await page.waitForFunction(([t, drawn]) => window.nmdpView.time > t && window.nmdpView.rendered > drawn,
      [startTime, startDrawn], { timeout: 20000 });
    const paused = await page.evaluate(async () => {
      window.nmdpView.pause();
      const at = window.nmdpView.time;
      await new Promise((resolve) => setTimeout(resolve, 300));
      return [at, window.nmdpView.time];
    });
    assert.equal(paused[1], paused[0], "the time moved after pause()");
    await page.close();
  });

  it("opens a run whose URDF is gone and says so", async () => {
    const dir = path.join(tmp, "moved");
    fs.mkdirSync(dir);
    const urdf = path.join(dir, "quadruped.urdf");
    fs.copyFileSync(path.join(sourceDir, "models", "quadruped", "quadruped.urdf"), urdf);
    const file = path.join(dir, "gone.h5");
    simulate(file, "duration=0.5", `robot.urdf=${urdf}`);
    fs.rmSync(urdf);
    // Also without the URDF text the file carries: a file of an older nmdp.
    execFileSync("/usr/bin/python3", ["-c",
      "import h5py, sys\nwith h5py.File(sys.argv[1], 'r+') as f:\n    if 'model/urdf' in f: del f['model/urdf']", file]);
    const html = path.join(dir, "gone.html");
    view(html, file);
    const page = await openPage(browser.context, html);
    assert.equal(await page.title(), "nmdp view: ready (11 frames)");
    const warnings = await warningsOf(page);
    assert.ok(warnings.some((w) => /urdf/i.test(w) && w.includes("gone.h5")), `warnings: ${JSON.stringify(warnings)}`);
    assert.ok(await page.isVisible("#nmdp-view-warnings"));
    await page.close();
  });

  it("opens a run killed by SIGKILL and says it was cut short", async () => {
    const file = path.join(tmp, "killed.h5");
    // 600 s of trot takes about 20 s to simulate: killed after 1 s it has written some of its 12001 rows.
    const child = spawn(nmdp, ["simulate", scene, "--quiet", "--set", "duration=600", "--out", file], { stdio: "ignore" });
    const exited = new Promise((resolve) => child.on("exit", (code, signal) => resolve(signal)));
    const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
    // Killed 1 s after the file appears (a busy machine may take a while to start it).
    for (let waited = 0; !fs.existsSync(file) && waited < 20000; waited += 50) await sleep(50);
    await sleep(1000);
    child.kill("SIGKILL");
    assert.equal(await exited, "SIGKILL");
    const html = path.join(tmp, "killed.html");
    view(html, file);
    const payload = readPayload(html);
    assert.equal(payload.runs[0].status, "running");
    assert.ok(payload.runs[0].frames >= 1 && payload.runs[0].frames < 12001, `${payload.runs[0].frames} frames`);
    const page = await openPage(browser.context, html);
    assert.equal(await page.title(), `nmdp view: ready (${payload.runs[0].frames} frames)`);
    const warnings = await warningsOf(page);
    assert.ok(warnings.some((w) => /running|cut short/.test(w) && w.includes("killed.h5")), `warnings: ${JSON.stringify(warnings)}`);
    assert.ok(await page.isVisible("#nmdp-view-warnings"));
    await page.close();
  });

  it("shows an error in the page and the title when the payload cannot be read", async () => {
    const script = fs.readFileSync(bundle, "utf8");
    const html = path.join(tmp, "bad.html");
    const payload = JSON.stringify({ format: "nmdp-view", version: 2, runs: [] });
    fs.writeFileSync(html, '<!doctype html><html><head><meta charset="utf-8"><title>nmdp view: loading</title></head><body>' +
      `<script type="application/json" id="nmdp-view-data">${payload}</script>` +
      `<script>${script.replaceAll("</script", "<\\/script")}</script></body></html>`);
    const page = await openPage(browser.context, html);
    assert.equal(await page.title(), "nmdp view: error (payload version 2, this viewer reads version 1)");
    assert.ok(await page.isVisible("#nmdp-view-error"));
    assert.match(await page.textContent("#nmdp-view-error"), /payload version 2/);
    await page.close();
  });

  it("overlays two runs with one legend entry each", async () => {
    const second = path.join(tmp, "T25.h5");
    simulate(second, "duration=1", "integrator.dt=0.025");
    const html = path.join(tmp, "two.html");
    view(html, path.join(tmp, "T.h5"), second);
    const page = await openPage(browser.context, html);
    assert.equal(await page.title(), "nmdp view: ready (21 frames)");
    const legend = await page.$$eval("#nmdp-view-legend li", (items) => items.map((li) => li.textContent));
    assert.equal(legend.length, 2, JSON.stringify(legend));
    assert.ok(legend[0].includes("T.h5") && legend[1].includes("T25.h5"), JSON.stringify(legend));
    // One time cursor for both: to the end of the longer, in steps of the finer run's dt.
    assert.ok(Math.abs(Number(await page.getAttribute("#nmdp-view-time", "max")) - 1) < 1e-9);
    assert.ok(Math.abs(Number(await page.getAttribute("#nmdp-view-time", "step")) - 0.025) < 1e-9);
    await page.close();
  });
});
