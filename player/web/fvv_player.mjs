// The web player: a stream on any static HTTP server, played in a canvas.
// The playback loop is the module's (FvvPlayback: playhead, waits, time and
// fetch budgets, the cameras a GOP decodes); this file only carries out what
// it asks: fetch a GOP's fragment prefixes (FvvStream), decode them in the
// Web Worker, draw the frame it shows with Renderer II in WebGL 2
// (FvvRenderer), and turn the viewer's input into the view.
//
//   const player = await FvvPlayer.open(canvas, 'take.fvv', { onNotice, onError });
//   player.play(); player.pause(); player.seek(frame); player.step(+1);
//   player.stats();   // what the HUD shows
//
// A stream without an index cannot be fetched by ranges: it plays from the
// start as it downloads, whole fragments, without seeking (onNotice says so).

import { FvvDecoderPool } from './fvv_decoder_pool.mjs';
import { FvvPlayback } from './fvv_playback.mjs';
import { FvvRenderer } from './fvv_renderer.mjs';
import { FvvStream, FvvStreamError } from './fvv_stream.mjs';
import { lookAtView, lookedAtPoint, orbitView } from './fvv_view.mjs';

const here = (name) => new URL(name, import.meta.url).href;
const DEFAULTS = () => ({
  moduleUrl: here('./fvv_decoder.mjs'), workerUrl: here('./fvv_decoder_worker.mjs'),
  zstdUrl: here('./fzstd/index.mjs'), shaderUrl: here('./shaders/'), autoplay: true, loop: true,
  onNotice: () => {}, onError: () => {},
  // Time every frame's WebGL work (a benchmark's ?time=frames), not every 8th.
  timeEveryFrame: new URLSearchParams(location.search).get('time') === 'frames',
  // Decoder workers, each decoding its share of a frame's cameras: half the
  // cores, the rest left to drawing (with software WebGL on two cores, a
  // second decoder slowed playback: docs/web.md).
  decoders: Number(new URLSearchParams(location.search).get('decoders')) ||
    Math.max(1, Math.min(4, Math.floor((navigator.hardwareConcurrency ?? 2) / 2))),
});
// GOPs of decoded frames kept (the one shown, the ones fetched ahead).
const CACHED_GOPS = 4;

export class FvvPlayer {
  // options: moduleUrl, workerUrl, zstdUrl, shaderUrl (defaults: beside this
  // file, as the build lays the site out), prepared (FvvPlayer.prepare's),
  // onNotice(text), onError(error), onGop({ gop, cameras, fetched,
  // fetchBytes, seconds, whole, started, ended, frames }) after each GOP is
  // decoded (whole: its fragments were fetched whole; seconds: the link's
  // time charged to its fetch; started, ended: the fetch's, in
  // performance.now() ms), autoplay (true), loop (true).
  static async open(canvas, url, options = {}) {
    const p = new FvvPlayer(canvas, options);
    try {
      await p.#open(url);
    } catch (e) {
      p.destroy();
      throw e;
    }
    return p;
  }

  // What a page can ready before it has a stream: the module compiled once
  // (the page's loop and the worker's decoder instantiate it) and the worker
  // started. A player opened with it fetches nothing but the stream.
  static async prepare(options = {}) {
    const o = { ...DEFAULTS(), ...options };
    const wasmUrl = new URL(o.moduleUrl.replace(/\.mjs$/, '.wasm'), location.href);
    const response = await fetch(wasmUrl);
    if (!response.ok) throw new Error(`${wasmUrl}: the server answered ${response.status}`);
    const wasmModule = await WebAssembly.compileStreaming(response);
    const worker = await FvvDecoderPool.create(o.workerUrl,
      { moduleUrl: o.moduleUrl, zstdUrl: o.zstdUrl, wasmModule }, o.decoders);
    await import(o.moduleUrl);
    return { wasmModule, worker, used: false };
  }

  constructor(canvas, options) {
    this.canvas = canvas;
    this.options = { ...DEFAULTS(), ...options };
    // options.gl: a WebGL 2 context that another renderer owns (a three.js
    // scene: fvv_three.mjs); its owner then drives the player (update, draw).
    this.external = Boolean(options.gl);
    const gl = options.gl ?? canvas.getContext('webgl2', { antialias: false });
    if (!gl) throw new Error('this browser has no WebGL 2');
    this.gl = gl;
    this.gops = new Map();    // GOP -> decoded frames
    // GOPs' fetches under way (the loop allows two), each with the link's
    // time charged to it so far (#chargeLink).
    this.fetches = new Set();
    this.linkClock = 0;
    this.decoding = false;    // a GOP being decoded
    this.fetchedGops = new Map();  // GOP -> its fetch, until it is decoded
    this.error = null;
    this.orbit = { yaw: 0, pitch: 0.11, distance: 3.5, fovDeg: 40 };
    this.viewDirty = true;
    this.hud = { fps: 0, webglMs: 0, lastGopBytes: 0, lastGopBudget: 0, lastCameras: [] };
    this.drawTimes = [];
    this.pixel = new Uint8Array(4);
    this.drawCount = 0;
  }

  async #open(url) {
    const o = this.options;
    // A prepared worker serves one player; a second player starts its own.
    const prepared = o.prepared && !o.prepared.used ? o.prepared : null;
    if (prepared) prepared.used = true;
    this.wasmModule = o.prepared?.wasmModule;
    this.worker = prepared?.worker ?? await FvvDecoderPool.create(o.workerUrl,
      { moduleUrl: o.moduleUrl, zstdUrl: o.zstdUrl, wasmModule: this.wasmModule }, o.decoders);
    try {
      this.stream = await FvvStream.open(url, this.worker, { onNotice: o.onNotice, headBytes: o.headBytes ?? 16384 });
      this.sequential = false;
    } catch (e) {
      if (!/has no index/.test(e.message)) throw e;
      o.onNotice('this stream has no index: it plays from the start as it downloads, whole ' +
                 'fragments, and cannot seek');
      // A fresh decoder for the pushed bytes: the other one was opened for ranges.
      this.worker.terminate();
      this.worker = await FvvDecoderPool.create(o.workerUrl,
        { moduleUrl: o.moduleUrl, zstdUrl: o.zstdUrl, wasmModule: this.wasmModule }, o.decoders);
      this.stream = await SequentialStream.open(url, this.worker, o.onNotice);
      this.sequential = true;
    }
    const info = this.stream.info;
    this.info = info;
    this.cameras = [];
    for (let c = 0; c < info.cameraCount; ++c) this.cameras.push(await this.worker.camera(c));
    // Until the first frame places the actor, the view orbits where the
    // cameras aim: the first GOPs are fetched for the cameras that view
    // will blend, not for a guess's.
    this.aim = lookedAtPoint(this.cameras) ?? [0, 1, 0];
    const model = await this.worker.model();
    // The simplified body for the depth maps, off the page's thread (a large
    // model takes seconds); a stream with masks draws none.
    const depthTriangles = info.hasMasks ? undefined : await this.worker.depthMapTriangles();
    this.playback = await FvvPlayback.create({
      moduleUrl: o.moduleUrl, wasmModule: this.wasmModule, info, centres: this.cameras.map((c) => c.centre),
    });
    this.playback.setTransport({ playing: o.autoplay, loop: o.loop && !this.sequential, speed: 1 });
    // The head's fetches measured the network first: the first GOP's budget.
    if (this.stream.fetched > 0 && this.stream.fetchSeconds > 0) {
      this.playback.fetchMeasured(this.stream.fetched, this.stream.fetchSeconds);
    }
    this.renderer = await FvvRenderer.create(this.gl, {
      shaderUrl: o.shaderUrl, model, cameras: this.cameras, info, playback: this.playback, depthTriangles,
    });
    this.last = performance.now();
    this.running = true;
    if (this.external) return;
    this.#attachInput();
    this.tick = (now) => this.#frame(now);
    requestAnimationFrame(this.tick);
  }

  // For an owner that draws (options.gl): moves the playhead on by dt
  // seconds for a viewer at `eye` looking at `target` (the stream's world),
  // serves what the loop asks and readies the frame to show. True when a
  // frame is ready to draw.
  update(dt, eye, target) {
    if (this.error) return Boolean(this.shownFrame);
    this.playback.advance(dt, eye, target);
    this.#serve();
    this.#decodeNext();
    const s = this.playback.state();
    if (!s.hasFrame) return false;
    const frame = this.gops.get(Math.floor(s.frame / this.info.gopFrames))?.[s.frame % this.info.gopFrames];
    if (frame && frame !== this.shownFrame) {
      this.renderer.setFrame(frame);
      this.shownFrame = frame;
    }
    return Boolean(this.shownFrame);
  }

  // Draws the frame update() readied into the owner's scene: its depth
  // buffer tested, nothing cleared (FvvRenderer.draw's options).
  drawInto(view, width, height, options = {}) {
    if (!this.shownFrame) return [];
    const blended = this.renderer.draw(view, width, height, { clear: false, ...options });
    this.playback.frameDrawn(0);
    return blended;
  }

  destroy() {
    this.running = false;
    this.detachInput?.();
    this.playback?.destroy();
    this.worker?.terminate();
  }

  play() { this.#transport({ playing: true }); }
  pause() { this.#transport({ playing: false }); }
  get playing() { return this.playback.state().playing; }
  seek(frame) {
    if (this.sequential) return;
    this.playback.seek(Math.max(0, Math.min(this.info.frameCount - 1, Math.round(frame))));
  }
  step(delta) {
    this.pause();
    const s = this.playback.state();
    this.seek((s.hasFrame ? s.frame : 0) + delta);
  }
  #transport(change) {
    const s = this.playback.state();
    this.playback.setTransport({ playing: s.playing, loop: this.options.loop && !this.sequential,
                                 speed: 1, ...change });
  }

  // The view: the orbit round the actor, or a fixed one (eye, target, fovDeg).
  setView(view) {
    this.fixedView = view;
    this.viewDirty = true;
  }
  #view() {
    const aspect = this.canvas.width / this.canvas.height;
    const target = this.renderer.actor ?? this.aim;
    if (this.fixedView) return lookAtView(this.fixedView.eye, this.fixedView.target, this.fixedView.fovDeg ?? 40, aspect);
    return orbitView(target, { ...this.orbit, aspect });
  }

  stats() {
    const s = this.playback.state();
    return { ...s, ...this.hud, frameCount: this.info.frameCount, error: this.error?.message ?? null,
             sequential: this.sequential };
  }

  // One tick of the page: move the playhead, serve what the loop asks, draw.
  #frame(now) {
    if (!this.running) return;
    const dt = Math.min(0.25, (now - this.last) / 1000);
    this.last = now;
    try {
      const view = this.#view();
      this.playback.advance(dt, view.eye, view.target);
      this.#serve();
      this.#decodeNext();
      const s = this.playback.state();
      if (s.hasFrame && (s.changed || this.viewDirty || !this.shownFrame)) {
        const frames = this.gops.get(Math.floor(s.frame / this.info.gopFrames));
        const frame = frames?.[s.frame % this.info.gopFrames];
        if (frame) {
          // Every 8th frame (every frame with options.timeEveryFrame, for
          // benchmarks), the frame's WebGL time, not only its commands':
          // reading a pixel back waits for the drawing (finish() does not, in
          // chromium), which holds up the frame it is done on; once before
          // the frame too, so that earlier frames' work is not counted. Not
          // the first: the software rasteriser compiles its pipelines then
          // (0.4 s here), which would hold this thread while the next GOP's
          // decode waits to be started.
          const timed = this.options.timeEveryFrame || ++this.drawCount % 8 === 0;
          const sync = () => this.gl.readPixels(0, 0, 1, 1, this.gl.RGBA, this.gl.UNSIGNED_BYTE, this.pixel);
          if (timed && !this.options.timeEveryFrame) sync();
          const t0 = performance.now();
          if (frame !== this.shownFrame) this.renderer.setFrame(frame);
          this.shownFrame = frame;
          // The view again: an orbit follows the actor of the frame just set.
          this.hud.lastCameras = this.renderer.draw(this.#view(), this.canvas.width, this.canvas.height);
          if (timed) sync();
          const ms = performance.now() - t0;
          if (timed) this.hud.webglMs = this.hud.webglMs ? 0.7 * this.hud.webglMs + 0.3 * ms : ms;
          this.hud.webglTotalMs = (this.hud.webglTotalMs ?? 0) + (this.options.timeEveryFrame ? ms : this.hud.webglMs);
          this.playback.frameDrawn(this.hud.webglMs);
          this.viewDirty = false;
          this.drawTimes.push(now);
        }
      }
      while (this.drawTimes.length && this.drawTimes[0] < now - 1000) this.drawTimes.shift();
      this.hud.fps = this.drawTimes.length;
    } catch (e) {
      this.#fail(e);
    }
    requestAnimationFrame(this.tick);
  }

  #fail(e) {
    if (this.error) return;
    this.error = e;
    this.pause();
    this.options.onError(e);
  }

  // Serves the loop's requests in two stages, so that the network never
  // waits for the decoder: fetches of GOPs' fragment prefixes (as the loop's
  // fetch budget allows), running up to two seconds ahead, two at a time
  // where the loop allows (the next request's round trip overlaps the last
  // one's bytes), and decodes in the worker of the fetched GOPs the loop says
  // are due (#decodeNext).
  async #serve() {
    if (this.error || !this.running) return;
    const r = this.playback.nextRequest();
    if (!r) return;
    const fetch = { seconds: 0, started: performance.now() };
    this.#chargeLink();
    this.fetches.add(fetch);
    this.#serve();  // a second fetch beside this one, where the loop allows it
    try {
      const { fetched, parts, cameras, whole } = await this.stream.fetchGopBytes(r.gop, r.cameras,
        r.fetchBytes > 0 ? r.fetchBytes : Number.MAX_SAFE_INTEGER, this.playback);
      this.#chargeLink();
      this.fetches.delete(fetch);
      const seconds = fetch.seconds;
      if (fetched > 0 && seconds > 0) this.playback.fetchMeasured(fetched, seconds);
      this.hud.lastGopBytes = fetched;
      this.hud.lastGopBudget = r.fetchBytes;
      // The bytes go to the worker at once: it takes its messages in the
      // order they were sent, so a decode asked for later finds them there,
      // without waiting for this message's answer (which waits for this
      // thread, busy drawing). Cameras whose fragments lost their heads to
      // a closed connection are left out of the GOP's decode.
      this.stream.addParts(parts).catch((e) => this.#fail(e));
      this.fetchedGops.set(r.gop, {
        fetched, fetchBytes: r.fetchBytes, seconds, whole: whole ?? true,
        started: fetch.started, ended: performance.now(),
        cameras: cameras ?? r.cameras,
      });
      this.playback.fetched(r.gop);
    } catch (e) {
      this.playback.failed(r.gop);
      this.#fail(e instanceof FvvStreamError ? e : new Error(`GOP ${r.gop}: ${e.message}`));
    } finally {
      this.#chargeLink();
      this.fetches.delete(fetch);
    }
    this.#decodeNext();
    this.#serve();  // the next fetch at once, not at the next frame
  }

  // Charges the time since the last call to the fetches under way, split
  // evenly: two that share the link each take half of it, so each fetch's
  // bytes over its time tell the link's rate, as one fetch alone does.
  #chargeLink() {
    const now = performance.now();
    for (const f of this.fetches) f.seconds += (now - this.linkClock) / 1000 / this.fetches.size;
    this.linkClock = now;
  }

  // Runs `work` after the decodes queued before it on the worker.
  #inOrder(work) {
    const run = (this.decodes ?? Promise.resolve()).then(work);
    this.decodes = run.catch(() => {});
    return run;
  }

  #decodeNext() {
    if (this.decoding || this.error || !this.running) return;
    const d = this.playback.nextDecode();
    if (!d) return;
    this.decoding = true;
    const f = this.fetchedGops.get(d.gop) ?? { fetched: 0, fetchBytes: 0, seconds: 0, whole: true };
    this.fetchedGops.delete(d.gop);
    // The cameras whose fragments arrived, of those it was fetched for.
    const cameras = f.cameras ? d.cameras.filter((c) => f.cameras.includes(c)) : d.cameras;
    this.#inOrder(() => this.#decode({ ...d, cameras }, f)).finally(() => {
      this.decoding = false;
      this.#decodeNext();
      this.#serve();  // a delivery may let the loop ask for the next GOP
    });
  }

  async #decode(r, f) {
    if (this.error) return;
    try {
      const first = r.gop * this.info.gopFrames;
      const count = Math.min(this.info.gopFrames, this.info.frameCount - first);
      const t0 = performance.now();
      // The GOP's frames in one message: each message's answer waits for the
      // page's thread, which draws meanwhile (a frame per message cost a GOP
      // about 0.2 s on two cores).
      const frames = await this.worker.decodeFrames(first, count, {
        cameras: r.cameras, maxMs: r.maxMs, floorShare: r.floorShare,
      });
      for (const frame of frames) this.stream.surfaceLearned(frame);
      this.gops.set(r.gop, frames);
      // The loop's decode time is the worker's whole time for the GOP: its
      // frames' RGB and their way to the page too, which no budget cuts but
      // the controller must leave room for.
      this.playback.deliver(r.gop, { ...frames[0].report, decodeMs: performance.now() - t0 },
        r.cameras.length);
      this.options.onGop?.({ gop: r.gop, cameras: r.cameras, fetched: f.fetched, fetchBytes: f.fetchBytes,
                             seconds: f.seconds, whole: f.whole, started: f.started, ended: f.ended,
                             frames });
      this.hud.report = frames[0].report;
      this.#evict();
    } catch (e) {
      this.playback.failed(r.gop);
      this.#fail(new Error(`GOP ${r.gop}: ${e.message}`));
    }
  }

  // Keeps the GOP shown and those next in playing order (round the loop's end).
  #evict() {
    const s = this.playback.state();
    const shown = s.hasFrame ? Math.floor(s.frame / this.info.gopFrames) : 0;
    const n = Math.ceil(this.info.frameCount / this.info.gopFrames);
    const ahead = (g) => (g - shown + n) % n;
    const gops = [...this.gops.keys()].sort((a, b) => ahead(a) - ahead(b));
    for (const g of gops.slice(CACHED_GOPS)) {
      this.gops.delete(g);
      this.playback.forget(g);
    }
  }

  // A still of `frame` from a fixed view (eye, target, fovDeg), decoded whole
  // (or each fragment's texture cut at `bytes`) for every camera, as `fvv
  // render --path` draws it, at width x height: for comparing the page with
  // the native renderer. Stops playback. Returns top-down RGB8.
  async still(frame, view, { bytes = 0, width, height } = {}) {
    this.pause();
    this.running = false;
    if (width && height) {
      this.canvas.width = width;
      this.canvas.height = height;
    }
    // In the decode chain, behind the bytes already fetched for it.
    const gop = Math.floor(frame / this.info.gopFrames);
    const decoded = await this.#inOrder(async () => {
      await this.stream.fetchGop(gop, undefined, Number.MAX_SAFE_INTEGER);
      return this.worker.decodeFrame(frame, { maxBytes: bytes });
    });
    this.renderer.setFrame(decoded);
    const w = this.canvas.width, h = this.canvas.height;
    this.renderer.draw(lookAtView(view.eye, view.target, view.fovDeg ?? 40, w / h), w, h);
    return this.renderer.readRgb(w, h);
  }

  // Orbit by dragging (mouse, pen or one finger), zoom by the wheel or a pinch.
  #attachInput() {
    const c = this.canvas, pointers = new Map();
    let pinch = 0;
    const down = (e) => {
      c.setPointerCapture(e.pointerId);
      pointers.set(e.pointerId, [e.clientX, e.clientY]);
    };
    const move = (e) => {
      const before = pointers.get(e.pointerId);
      if (!before) return;
      pointers.set(e.pointerId, [e.clientX, e.clientY]);
      if (pointers.size === 1) {
        this.orbit.yaw -= (e.clientX - before[0]) * 0.01;
        this.orbit.pitch = Math.max(-1.2, Math.min(1.2, this.orbit.pitch + (e.clientY - before[1]) * 0.01));
      } else if (pointers.size === 2) {
        const [a, b] = [...pointers.values()];
        const d = Math.hypot(a[0] - b[0], a[1] - b[1]);
        if (pinch > 0) this.#zoom(pinch / d);
        pinch = d;
      }
      this.fixedView = null;
      this.viewDirty = true;
    };
    const up = (e) => {
      pointers.delete(e.pointerId);
      pinch = 0;
    };
    const wheel = (e) => {
      e.preventDefault();
      this.#zoom(Math.exp(e.deltaY * 0.001));
    };
    c.style.touchAction = 'none';
    c.addEventListener('pointerdown', down);
    c.addEventListener('pointermove', move);
    c.addEventListener('pointerup', up);
    c.addEventListener('pointercancel', up);
    c.addEventListener('wheel', wheel, { passive: false });
    this.detachInput = () => {
      c.removeEventListener('pointerdown', down);
      c.removeEventListener('pointermove', move);
      c.removeEventListener('pointerup', up);
      c.removeEventListener('pointercancel', up);
      c.removeEventListener('wheel', wheel);
    };
  }
  #zoom(factor) {
    this.orbit.distance = Math.max(0.5, Math.min(20, this.orbit.distance * factor));
    this.fixedView = null;
    this.viewDirty = true;
  }
}

// A stream without an index, fetched whole in one request and pushed to the
// decoder in order as it arrives (the decoder's streaming input): GOPs play
// as their bytes come; FvvStream's interface, without ranges.
class SequentialStream {
  static async open(url, worker, onNotice) {
    const s = new SequentialStream(url, worker, onNotice);
    await s.#start();
    return s;
  }
  constructor(url, worker, onNotice) {
    this.url = url;
    this.worker = worker;
    this.notice = onNotice;
    this.fetched = 0;
    this.available = 0;
    this.ended = false;
    this.waiters = [];
  }
  async #start() {
    const response = await fetch(this.url, { cache: 'no-store' });
    if (!response.ok) throw new FvvStreamError(`${this.url}: the server answered ${response.status}`);
    this.reader = response.body.getReader();
    while (!this.info) {
      if (!(await this.#pump())) throw new FvvStreamError(`${this.url}: the stream ends before its head does`);
    }
    if (this.info.frameCount === 0) {
      // A live stream counts its frames from its fragments: all of them first.
      this.notice('a live stream: it plays once it has arrived');
      while (await this.#pump());
      this.ended = true;
      this.info = { ...this.info, frameCount: this.available };
      if (this.available === 0) throw new FvvStreamError(`${this.url}: the stream holds no frame`);
      return;
    }
    this.#pumpAll();
  }
  // Pushes the next piece; false at the end.
  async #pump() {
    const { done, value } = await this.reader.read();
    if (done) {
      await this.worker.pushEnd();
    } else {
      this.fetched += value.length;
      await this.worker.push(value);
    }
    for (let event; (event = await this.worker.process()) !== 'need';) {
      if (event === 'ready' && !this.info) this.info = await this.worker.info();
      if (event === 'end') break;
    }
    this.available = await this.worker.framesAvailable();
    for (const w of this.waiters.splice(0)) w();
    return !done;
  }
  async #pumpAll() {
    try {
      while (await this.#pump());
    } catch (e) {
      this.error = e;
    }
    this.ended = true;
    for (const w of this.waiters.splice(0)) w();
  }
  async fetchGop(span) {
    return (await this.fetchGopBytes(span)).fetched;
  }
  async addParts() {}
  surfaceLearned() {}  // whole fragments: no fetch plan to inform
  // Waits until the GOP's frames decode: { fetched: the bytes fetched meanwhile }.
  // Two calls may wait at once (the player fetches two GOPs at a time):
  // each counts the bytes that came since the last call returned (the first,
  // every byte from the stream's start: the head's too), so each once.
  async fetchGopBytes(span) {
    const last = Math.min((span + 1) * this.info.gopFrames, this.info.frameCount);
    while (this.available < last) {
      if (this.error) throw new FvvStreamError(`${this.url}: ${this.error.message}`);
      if (this.ended) throw new FvvStreamError(`${this.url}: the stream ends at frame ${this.available}`);
      await new Promise((resolve) => this.waiters.push(resolve));
    }
    const fetched = this.fetched - (this.counted ?? 0);
    this.counted = this.fetched;
    return { fetched, parts: [] };
  }
}
