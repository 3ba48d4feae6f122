#!/usr/bin/env node
// Assembles a page the way the C++ program does (viewer/README.md, "The page template"):
//
//   node viewer/tools/assemble.mjs TEMPLATE BUNDLE CONFIG_JSON OUT_HTML
//
// TEMPLATE    viewer/src/page.html (exactly one line holding <!--TISSUEBENCH_BUNDLE-->
//             and one holding <!--TISSUEBENCH_CONFIG-->)
// BUNDLE      viewer/dist/viewer.js
// CONFIG_JSON a file holding the config: {"mode":"run","run":{...}} or {"mode":"live","ws":"/ws"};
//             a file holding bare run data (with "format": "tissuebench-view/1") is wrapped
//             as {"mode":"run","run":DATA}. "-" reads standard input.
//
// Escaping: every "</script" (and "</SCRIPT") in the bundle becomes "<\/script"; every "<" in the JSON
// becomes "\u003c" (the same string to JSON; outside strings JSON has no "<"). The JSON is written as read (no re-serialisation) unless it was wrapped.
// For development and tests only: the product is `tissuebench view` / `serve`.
import { readFileSync, writeFileSync } from 'node:fs';

export const BUNDLE_PLACEHOLDER = '<!--TISSUEBENCH_BUNDLE-->';
export const CONFIG_PLACEHOLDER = '<!--TISSUEBENCH_CONFIG-->';

// As leg/src/viewer.cpp does: "</script" and "</SCRIPT" (the only ways a bundle could end its
// element early in practice; esbuild's output holds neither).
export function escapeBundle(js) {
  return js.split('</script').join('<\\/script').split('</SCRIPT').join('<\\/SCRIPT');
}

export function escapeJson(json) {
  return json.split('<').join('\\u003c');
}

function findOnce(template, placeholder) {
  const at = template.indexOf(placeholder);
  if (at < 0) throw new Error(`template has no ${placeholder}`);
  if (template.indexOf(placeholder, at + placeholder.length) >= 0)
    throw new Error(`template has ${placeholder} more than once`);
  return at;
}

// Both placeholders are replaced at their places in the template (one pass), so text inside
// the inserted bundle or JSON is never taken for a placeholder. No String.replace: the bundle
// is full of "$&"-like sequences.
export function assemble(template, bundle, configJson) {
  const parts = [
    {
      at: findOnce(template, BUNDLE_PLACEHOLDER),
      len: BUNDLE_PLACEHOLDER.length,
      text: '<script>' + escapeBundle(bundle) + '</script>',
    },
    {
      at: findOnce(template, CONFIG_PLACEHOLDER),
      len: CONFIG_PLACEHOLDER.length,
      text: '<script id="tissuebench-config" type="application/json">' + escapeJson(configJson) + '</script>',
    },
  ].sort((a, b) => a.at - b.at);
  let out = '';
  let pos = 0;
  for (const p of parts) {
    out += template.slice(pos, p.at) + p.text;
    pos = p.at + p.len;
  }
  return out + template.slice(pos);
}

function main(argv) {
  if (argv.length !== 4) {
    process.stderr.write('usage: assemble.mjs TEMPLATE BUNDLE CONFIG_JSON OUT_HTML\n');
    return 2;
  }
  const [templatePath, bundlePath, configPath, outPath] = argv;
  const template = readFileSync(templatePath, 'utf8');
  const bundle = readFileSync(bundlePath, 'utf8');
  let config = readFileSync(configPath === '-' ? 0 : configPath, 'utf8').trim();
  // Bare run data (as run_from_h5.py writes it) is wrapped into a run-mode config.
  const head = config.slice(0, 200);
  if (/"format"\s*:\s*"tissuebench-view\//.test(head) && !/"mode"\s*:/.test(head))
    config = '{"mode":"run","run":' + config + '}';
  const html = assemble(template, bundle, config);
  writeFileSync(outPath, html);
  process.stderr.write(`${outPath}: ${html.length} bytes\n`);
  return 0;
}

if (import.meta.url === `file://${process.argv[1]}` || process.argv[1]?.endsWith('assemble.mjs')) {
  try {
    process.exitCode = main(process.argv.slice(2));
  } catch (e) {
    process.stderr.write(`assemble.mjs: ${e.message}\n`);
    process.exitCode = 1;
  }
}
