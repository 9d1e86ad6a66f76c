// The headless-browser harness fvv's web tests share: a static HTTP server on
// 127.0.0.1 (an ephemeral port) over the directories given, with byte ranges,
// no caching and the cross-origin isolation headers, Debian's chromium
// driven by puppeteer-core, and a guarantee that both are gone when the work is
// done or fails (the browser closed, then killed; the server closed).
//
//   import { withBrowser } from './browser_harness.mjs';
//   await withBrowser({ '/web/': webDir, '/data/': dataDir }, async ({ page, base, requests }) => {
//     await page.goto(base + '/web/view_gltf.html?...');
//   });
import { closeSync, createReadStream, openSync, readSync, statSync } from 'node:fs';
import { createServer } from 'node:http';
import path from 'node:path';
import puppeteer from 'puppeteer-core';

const TYPES = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript',
  '.json': 'application/json', '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json',
  '.bin': 'application/octet-stream', '.png': 'image/png', '.wasm': 'application/wasm',
  '.fvv': 'application/octet-stream',
};

// Serves GET /PREFIX/rest from mounts[PREFIX]/rest; nothing outside the mounts.
// As a static server or CDN does for a page fetching a stream: byte ranges
// ("Range: bytes=A-B", "A-", "-N") answered 206 with Content-Range, several
// ("bytes=A-B,C-D") as multipart/byteranges, a range past the end 416; no caching, so every fetch reaches the server; and
// the cross-origin isolation headers (COOP, COEP) that a page needs for
// SharedArrayBuffer. Every request is recorded in `log` (path, range, status,
// bytes sent). `faults` maps a path to what goes wrong there, as it does on
// real servers: { ignoreRange: true } answers every request with the whole
// file (200), { closeAfter: N, from: F } sends the first N bytes of every
// answer to a range from byte F on, and then drops the connection.
function serve(mounts, log, faults = {}) {
  const server = createServer((req, res) => {
    const url = decodeURIComponent(new URL(req.url, 'http://127.0.0.1').pathname);
    const entry = { path: url, range: req.headers.range ?? null, status: 404, bytes: 0 };
    const fault = faults[url] ?? {};
    log.push(entry);
    const headers = {
      'Cache-Control': 'no-store',
      'Cross-Origin-Opener-Policy': 'same-origin',
      'Cross-Origin-Embedder-Policy': 'require-corp',
      'Cross-Origin-Resource-Policy': 'same-origin',
      'Accept-Ranges': 'bytes',
    };
    for (const [prefix, dir] of Object.entries(mounts)) {
      if (!url.startsWith(prefix)) continue;
      const file = path.resolve(dir, url.slice(prefix.length));
      if (!file.startsWith(path.resolve(dir) + path.sep)) break;
      let size;
      try {
        const st = statSync(file);
        if (!st.isFile()) break;
        size = st.size;
      } catch {
        break;
      }
      headers['Content-Type'] = TYPES[path.extname(file)] ?? 'application/octet-stream';
      // Several ranges: one multipart/byteranges answer, as static servers give
      // (lighttpd, nginx); a fault's cut then falls in the multipart body.
      const several = /^bytes=\d+-\d+(,\s*\d+-\d+)+$/.exec(req.headers.range ?? '');
      if (several && !fault.ignoreRange) {
        const ranges = req.headers.range.slice(6).split(',').map((r) => r.trim().split('-').map(Number))
          .filter(([a, b]) => a < size && a <= b).map(([a, b]) => [a, Math.min(b, size - 1)]);
        if (ranges.length === 0) {
          entry.status = 416;
          res.writeHead(416, { ...headers, 'Content-Range': `bytes */${size}` }).end();
          return;
        }
        const boundary = 'fvvharness7c1d';
        const type = headers['Content-Type'];
        const pieces = [];
        for (const [a, b] of ranges) {
          pieces.push(Buffer.from(`--${boundary}\r\nContent-Type: ${type}\r\n` +
                                  `Content-Range: bytes ${a}-${b}/${size}\r\n\r\n`));
          pieces.push({ start: a, end: b });
          pieces.push(Buffer.from('\r\n'));
        }
        pieces.push(Buffer.from(`--${boundary}--\r\n`));
        const length = pieces.reduce((n, p) => n + (Buffer.isBuffer(p) ? p.length : p.end - p.start + 1), 0);
        entry.status = 206;
        entry.bytes = length;
        res.writeHead(206, { ...headers, 'Content-Type': `multipart/byteranges; boundary=${boundary}`,
                             'Content-Length': String(length) });
        const cutAt = fault.closeAfter !== undefined && ranges[0][0] >= (fault.from ?? 0)
          ? fault.closeAfter : Infinity;
        (async () => {
          let sent = 0;
          for (const p of pieces) {
            let data = p;
            if (!Buffer.isBuffer(p)) {
              data = Buffer.alloc(p.end - p.start + 1);
              const fd = openSync(file, 'r');
              try {
                readSync(fd, data, 0, data.length, p.start);
              } finally {
                closeSync(fd);
              }
            }
            if (sent + data.length > cutAt) data = data.subarray(0, cutAt - sent);
            if (data.length) await new Promise((resolve) => res.write(data, resolve));
            sent += data.length;
            if (sent >= cutAt) {
              entry.bytes = sent;
              setTimeout(() => res.destroy(), 50);
              return;
            }
          }
          res.end();
        })();
        return;
      }
      let first = 0, last = size - 1;
      const m = /^bytes=(\d*)-(\d*)$/.exec(req.headers.range ?? '');
      if (req.headers.range && m && (m[1] !== '' || m[2] !== '') && !fault.ignoreRange) {
        if (m[1] === '') {
          first = Math.max(0, size - Number(m[2]));
        } else {
          first = Number(m[1]);
          if (m[2] !== '') last = Math.min(last, Number(m[2]));
        }
        if (first >= size || first > last) {
          entry.status = 416;
          res.writeHead(416, { ...headers, 'Content-Range': `bytes */${size}` }).end();
          return;
        }
        entry.status = 206;
        headers['Content-Range'] = `bytes ${first}-${last}/${size}`;
      } else {
        entry.status = 200;
      }
      headers['Content-Length'] = String(last - first + 1);
      entry.bytes = last - first + 1;
      res.writeHead(entry.status, headers);
      if (req.method === 'HEAD' || size === 0) {
        res.end();
        return;
      }
      if (fault.closeAfter !== undefined && first >= (fault.from ?? 0) &&
          fault.closeAfter < last - first + 1) {
        // The promised length, then the connection dropped part way.
        entry.bytes = fault.closeAfter;
        const cut = createReadStream(file, { start: first, end: first + fault.closeAfter - 1 });
        cut.on('end', () => setTimeout(() => res.destroy(), 50));
        cut.pipe(res, { end: false });
        return;
      }
      createReadStream(file, { start: first, end: last }).pipe(res);
      return;
    }
    res.writeHead(404, headers).end('not found');
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

// `server`: the base URL of a server already running (lighttpd with
// tools/web/lighttpd.conf, serving the same paths) instead of the harness's
// own; `requests` is then null.
export async function withBrowser(mounts, work, { timeoutMs = 60000, faults = {}, server: external } = {}) {
  const requests = external ? null : [];
  const server = external ? null : await serve(mounts, requests, faults);
  const base = external ?? `http://127.0.0.1:${server.address().port}`;
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
      // FVV_CHROMIUM_GL: other flags for WebGL's back end, e.g. Mesa's llvmpipe
      // through ANGLE's OpenGL in a virtual display (bench/run_web_player_bench.sh).
      args: ['--no-sandbox',
             ...(process.env.FVV_CHROMIUM_GL?.split(' ') ?? ['--use-angle=swiftshader', '--enable-unsafe-swiftshader']),
             '--disable-dev-shm-usage', '--hide-scrollbars', '--disable-crash-reporter',
             '--disable-breakpad'],
    });
    const page = await browser.newPage();
    page.on('console', (m) => console.log(`page: ${m.text()}`));
    page.on('pageerror', (e) => console.error(`page error: ${e.message}`));
    return await work({ page, base, requests });
  } finally {
    clearTimeout(timer);
    if (browser) {
      const child = browser.process();
      await browser.close().catch(() => {});
      if (child && child.exitCode === null) child.kill('SIGKILL');
    }
    if (server) await new Promise((resolve) => server.close(resolve));
  }
}
