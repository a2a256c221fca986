// Launches Debian's chromium headless through playwright-core, as the tests and the README's
// screenshot do. `npx playwright install` cannot download a browser here: the system's is used.
import { chromium } from "playwright-core";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";

export const CHROMIUM = process.env.NMDP_CHROMIUM || "/usr/bin/chromium";

// --no-sandbox: chromium as root (CI) needs it. The background-networking flags keep chromium from
// trying to reach the network at start (CI machines have none).
// WebGL without a GPU: SwiftShader, chromium's software renderer. Debian's chromium 156, headless,
// already falls back to it on a machine without a GPU (three.js renders with no flag at all, and with
// --disable-gpu too; the renderer reads "ANGLE (Google, Vulkan 1.3.0 (SwiftShader Device
// (Subzero)...), SwiftShader driver)", and playwright-core adds --enable-unsafe-swiftshader itself).
// --use-angle=swiftshader --enable-unsafe-swiftshader ask for it explicitly: the same renderer, so the
// same pixels, on a machine with a GPU, and WebGL still there in a chromium that drops the fallback.
export const CHROMIUM_ARGS = [
  "--no-sandbox", "--disable-quic", "--no-first-run", "--disable-background-networking",
  "--disable-component-update", "--disable-sync", "--disable-default-apps",
  "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
];

export async function launchBrowser(viewport = { width: 800, height: 600 }) {
  if (!fs.existsSync(CHROMIUM)) {
    throw new Error(`${CHROMIUM} is missing: install Debian's chromium (scripts/install-deps.sh)`);
  }
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), "nmdp-view-chromium-"));
  const context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: CHROMIUM, headless: true, args: CHROMIUM_ARGS,
    viewport, deviceScaleFactor: 1,
  });
  return {
    context,
    async close() {
      await context.close();
      fs.rmSync(userDataDir, { recursive: true, force: true });
    },
  };
}

// Opens a page file with hash parameters and waits until it says it is ready (or has failed).
export async function openPage(context, file, hash = "", timeout = 30000) {
  const page = await context.newPage();
  const errors = [];
  page.on("pageerror", (e) => errors.push(e.message));
  await page.goto(`file://${path.resolve(file)}${hash ? "#" + hash : ""}`);
  await page.waitForFunction(() => /^nmdp view: (ready|error)/.test(document.title), null, { timeout });
  page.nmdpErrors = errors;
  return page;
}
