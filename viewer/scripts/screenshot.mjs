// Screenshot of a page of `nmdp view` in headless chromium, set up as the tests set it up
// (test/browser.mjs), e.g. the README's picture of the demo:
//   node viewer/scripts/screenshot.mjs demo/trot.html docs/images/nmdp-view.png [hash]
// The default hash shows the demo at 6 s with the follow camera and the plot panel.
import { launchBrowser, openPage } from "../test/browser.mjs";

const [page, out, hash = "t=6"] = process.argv.slice(2);
if (!page || !out) {
  console.error("usage: node viewer/scripts/screenshot.mjs PAGE.html OUT.png [HASH, e.g. t=6&panel=0]");
  process.exit(2);
}
const browser = await launchBrowser({ width: 1280, height: 720 });
try {
  const tab = await openPage(browser.context, page, hash);
  const title = await tab.title();
  if (!title.startsWith("nmdp view: ready")) throw new Error(`${page}: ${title}`);
  await tab.screenshot({ path: out });
  console.log(`${out}: ${title}`);
} finally {
  await browser.close();
}
