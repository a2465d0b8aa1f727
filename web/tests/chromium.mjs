// The headless Chromium the browser test and the benchmarks launch: Debian's chromium
// (CHROMIUM), software WebGL (SwiftShader), no network services of its own, a fresh profile in
// `dir`.
import fs from 'node:fs';
import path from 'node:path';
import { chromium } from 'playwright-core';

/** A persistent context in a new profile folder under `dir`, with a `viewport`. */
export function launchChromium(dir, viewport = { width: 1000, height: 640 }) {
  return chromium.launchPersistentContext(fs.mkdtempSync(path.join(dir, 'profile-')), {
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    headless: true,
    viewport,
    args: [
      '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    ],
  });
}
