// Bundles src/main.js into dist/nmdp-view.js: one minified IIFE with its CSS inside (loaded as text
// and injected by the script), so that `nmdp view` can inline it verbatim into a page that needs no
// other file and no network.
import { build } from "esbuild";
import { fileURLToPath } from "node:url";
import path from "node:path";

const root = path.dirname(path.dirname(fileURLToPath(import.meta.url)));
await build({
  entryPoints: [path.join(root, "src/main.js")],
  outfile: path.join(root, "dist/nmdp-view.js"),
  bundle: true,
  format: "iife",
  minify: true,
  target: ["es2020"],
  loader: { ".css": "text" },
  legalComments: "none",
  logLevel: "warning",
});
