// Compares source files with Dolos for `raylab similarity`.
//
// Usage: node compare.mjs MANIFEST.json
// The manifest: {"language": "rust", "template": PATH or null, "files": [PATH, ...]}. Each file
// is one submission (a student's sources of one lab, joined); the template is the starter code,
// whose fingerprints count for no pair. Prints one JSON object: {"dolos": VERSION,
// "warnings": [...], "pairs": [{"left": I, "right": J, "similarity": S, "longest": K,
// "left_lines": [FIRST, LAST], "right_lines": [FIRST, LAST]}, ...]}, where I and J index
// "files", S is Dolos's similarity (0 to 1), K the length of the longest shared fragment in
// k-grams, and the lines (1-based) those of that fragment in each file.
import { readFileSync } from "node:fs";
import { Dolos, File } from "@dodona/dolos-lib";

const manifest = JSON.parse(readFileSync(process.argv[2], "utf8"));
const read = (path) => new File(path, readFileSync(path, "utf8"));
const files = manifest.files.map(read);
const template = manifest.template ? read(manifest.template) : undefined;
const dolos = new Dolos({ language: manifest.language });
const report = await dolos.analyze(files, "raylab", template);
const index = new Map(files.map((file, i) => [file.path, i]));
const pairs = report.allPairs().map((pair) => {
  let longestFragment = null;
  for (const fragment of pair.buildFragments()) {
    if (longestFragment === null || fragment.pairs.length > longestFragment.pairs.length) {
      longestFragment = fragment;
    }
  }
  const lines = (region) => (region ? [region.startRow + 1, region.endRow + 1] : null);
  return {
    left: index.get(pair.leftFile.path),
    right: index.get(pair.rightFile.path),
    similarity: pair.similarity,
    longest: pair.longest,
    left_lines: lines(longestFragment?.leftSelection),
    right_lines: lines(longestFragment?.rightSelection),
  };
});
const installed = new URL("./node_modules/@dodona/dolos-lib/package.json", import.meta.url);
const version = JSON.parse(readFileSync(installed, "utf8")).version;
process.stdout.write(JSON.stringify({ dolos: version, warnings: report.warnings, pairs }));
