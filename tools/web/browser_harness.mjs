// The headless-browser harness fvv's web tests share: a static HTTP server on
// 127.0.0.1 (an ephemeral port) over the directories given, Debian's chromium
// driven by puppeteer-core, and a guarantee that both are gone when the work is
// done or fails (the browser closed, then killed; the server closed).
//
//   import { withBrowser } from './browser_harness.mjs';
//   await withBrowser({ '/web/': webDir, '/data/': dataDir }, async ({ page, base }) => {
//     await page.goto(base + '/web/view_gltf.html?...');
//   });
import { createReadStream, statSync } from 'node:fs';
import { createServer } from 'node:http';
import path from 'node:path';
import puppeteer from 'puppeteer-core';

const TYPES = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript',
  '.json': 'application/json', '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json',
  '.bin': 'application/octet-stream', '.png': 'image/png',
};

// Serves GET /PREFIX/rest from mounts[PREFIX]/rest; nothing outside the mounts.
function serve(mounts) {
  const server = createServer((req, res) => {
    const url = decodeURIComponent(new URL(req.url, 'http://127.0.0.1').pathname);
    for (const [prefix, dir] of Object.entries(mounts)) {
      if (!url.startsWith(prefix)) continue;
      const file = path.resolve(dir, url.slice(prefix.length));
      if (!file.startsWith(path.resolve(dir) + path.sep)) break;
      try {
        if (!statSync(file).isFile()) break;
      } catch {
        break;
      }
      res.writeHead(200, { 'Content-Type': TYPES[path.extname(file)] ?? 'application/octet-stream' });
      createReadStream(file).pipe(res);
      return;
    }
    res.writeHead(404).end('not found');
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

export async function withBrowser(mounts, work, { timeoutMs = 60000 } = {}) {
  const server = await serve(mounts);
  const base = `http://127.0.0.1:${server.address().port}`;
  let browser;
  const timer = setTimeout(() => {
    console.error(`browser harness: no result within ${timeoutMs} ms`);
    browser?.process()?.kill('SIGKILL');
    process.exit(1);
  }, timeoutMs);
  try {
    browser = await puppeteer.launch({
      executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
      headless: true,
      // Software WebGL (SwiftShader) on machines without a GPU; no sandbox for root in CI.
      // No crash reporter: its handler detaches from the browser and outlives it.
      args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
             '--disable-dev-shm-usage', '--hide-scrollbars', '--disable-crash-reporter',
             '--disable-breakpad'],
    });
    const page = await browser.newPage();
    page.on('console', (m) => console.log(`page: ${m.text()}`));
    page.on('pageerror', (e) => console.error(`page error: ${e.message}`));
    return await work({ page, base });
  } finally {
    clearTimeout(timer);
    if (browser) {
      const child = browser.process();
      await browser.close().catch(() => {});
      if (child && child.exitCode === null) child.kill('SIGKILL');
    }
    await new Promise((resolve) => server.close(resolve));
  }
}
