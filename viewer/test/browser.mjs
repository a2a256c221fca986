// Launches Debian's chromium headless through playwright-core, as the tests and the README's
// screenshot do. `npx playwright install` cannot download a browser here: the system's is used.
import { chromium } from "playwright-core";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";

export const CHROMIUM = process.env.NMDP_CHROMIUM || "/usr/bin/chromium";

// --no-sandbox: the tests run as root in CI. The background-networking flags keep chromium from
// calling out of a closed network (every refused connection otherwise costs time).
// WebGL without a GPU: --use-angle=swiftshader with --enable-unsafe-swiftshader gives three.js a
// software WebGL2 context (without the second flag chromium 156 refuses SwiftShader for WebGL and
// three.js fails with "Error creating WebGL context"); --ignore-gpu-blocklist keeps it from being
// blocked. --disable-gpu is NOT passed: it would turn WebGL off altogether.
export const CHROMIUM_ARGS = [
  "--no-sandbox", "--disable-quic", "--no-first-run", "--disable-background-networking",
  "--disable-component-update", "--disable-sync", "--disable-default-apps",
  "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist",
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
