// A stream on a static HTTP server, as a page plays it: the header boxes and
// the index by Range requests, then for each GOP a prefix of each fragment the
// view needs, as long as the bandwidth measured allows (the fetch plan compiled
// into the module: player/playback/fetch_plan.h). Works with an FvvDecoder or
// the Web Worker's FvvDecoderWorker (every call is awaited).
//
//   const stream = await FvvStream.open(url, decoder, { onNotice: (text) => ... });
//   await stream.fetchGop(0, [0, 1]);          // GOP 0 for cameras 0 and 1
//   const frame = await stream.frame(0, [0, 1]);
//
// Faults end in an FvvStreamError whose message says what happened (not
// found, the server's answer, a damaged or cut stream), never a hang: every
// request has a timeout. What arrived before a connection closed is kept:
// the decoder verifies it chunk by chunk (SPEC.md 3.5.1).

export class FvvStreamError extends Error {}

// The parts of a multipart/byteranges body: [{ range (its Content-Range),
// bytes }]. A body cut short keeps its whole parts and what came of the last.
function parseMultipart(body, boundary) {
  const text = new TextDecoder('latin1');
  const marker = new TextEncoder().encode(`--${boundary}`);
  const find = (from) => {
    outer: for (let i = from; i <= body.length - marker.length; ++i) {
      for (let k = 0; k < marker.length; ++k) if (body[i + k] !== marker[k]) continue outer;
      return i;
    }
    return -1;
  };
  const parts = [];
  for (let at = find(0); at >= 0;) {
    const headersEnd = (() => {
      for (let i = at; i + 3 < body.length; ++i) {
        if (body[i] === 13 && body[i + 1] === 10 && body[i + 2] === 13 && body[i + 3] === 10) return i;
      }
      return -1;
    })();
    if (headersEnd < 0) break;
    const headers = text.decode(body.subarray(at, headersEnd));
    const range = /content-range:\s*(bytes \d+-\d+\/\d+)/i.exec(headers)?.[1];
    const start = headersEnd + 4;
    const m = /bytes (\d+)-(\d+)/.exec(range ?? '');
    // The part's length from its Content-Range: its data may hold the marker's bytes.
    const length = m ? Number(m[2]) - Number(m[1]) + 1 : 0;
    parts.push({ range, bytes: body.subarray(start, Math.min(body.length, start + length)) });
    if (start + length >= body.length) break;
    at = find(start + length);
  }
  return parts;
}


export class FvvStream {
  // headBytes: the first request's length (the decoder asks for more as it needs).
  static async open(url, decoder, { timeoutMs = 10000, onNotice = () => {}, headBytes = 1 << 16 } = {}) {
    const s = new FvvStream(url, decoder, timeoutMs, onNotice);
    await s.#openHead(headBytes);
    return s;
  }

  constructor(url, decoder, timeoutMs, onNotice) {
    this.url = url;
    this.decoder = decoder;
    this.timeoutMs = timeoutMs;
    this.notice = onNotice;
    this.bandwidth = 0;       // bytes per second, measured (`measured` folded in)
    this.measured = [];       // fetches not yet folded in: [bytes, seconds]
    this.fetched = 0;         // every byte fetched, heads included
    this.fetchSeconds = 0;    // the time those fetches took, request to last byte
    this.wholeFile = false;   // the server ignored Range: the whole stream is held
  }

  // Bytes [offset, offset + size) of the stream: { bytes, total, complete }.
  // `complete` is false when the connection closed early (what came is kept).
  async #get(offset, size) {
    const { parts, total, whole, complete } = await this.#getRanges([[offset, size]]);
    if (whole) return { bytes: parts[0].bytes, total, whole, complete };
    if (parts.length === 0 || parts[0].offset !== offset) {
      if (parts.length === 0 && !complete) return { bytes: new Uint8Array(0), total, whole, complete };
      throw new FvvStreamError(`${this.url}: a range answer without a matching Content-Range`);
    }
    return { bytes: parts[0].bytes, total, whole, complete: complete && parts[0].bytes.length === size };
  }

  // Several ranges ([offset, size] each) in one request, as a server answers
  // them: { parts: [{ offset, bytes }], total, whole, complete, received (the
  // body's bytes, a multipart's own lines included) }. One range
  // is a plain 206; several a multipart/byteranges answer (a server may also
  // merge them into one range, or send the whole stream: 200, `whole`).
  async #getRanges(ranges) {
    const controller = new AbortController();
    const timer = setTimeout(() => controller.abort(), this.timeoutMs);
    const started = performance.now();
    let response;
    try {
      response = await fetch(this.url, {
        headers: { Range: 'bytes=' + ranges.map(([o, n]) => `${o}-${o + n - 1}`).join(',') },
        signal: controller.signal, cache: 'no-store',
      });
    } catch (e) {
      clearTimeout(timer);
      throw new FvvStreamError(`${this.url}: no answer (${e.name === 'AbortError' ? 'timed out' : e.message})`);
    }
    if (response.status === 404) {
      clearTimeout(timer);
      throw new FvvStreamError(`${this.url}: not found (404)`);
    }
    if (response.status === 416) {
      clearTimeout(timer);
      throw new FvvStreamError(`${this.url}: the stream ends before the bytes asked for (416: empty or cut)`);
    }
    if (response.status !== 206 && response.status !== 200) {
      clearTimeout(timer);
      throw new FvvStreamError(`${this.url}: the server answered ${response.status}`);
    }
    const chunks = [];
    let received = 0, complete = true;
    try {
      const reader = response.body.getReader();
      for (;;) {
        const { done, value } = await reader.read();
        if (done) break;
        chunks.push(value);
        received += value.length;
      }
    } catch {
      complete = false;  // closed mid-body: keep what came
    } finally {
      clearTimeout(timer);
    }
    const body = new Uint8Array(received);
    let at = 0;
    for (const c of chunks) {
      body.set(c, at);
      at += c.length;
    }
    const seconds = (performance.now() - started) / 1000;
    this.fetchSeconds += seconds;
    if (response.status === 200) {
      // A server that ignores Range sends the whole stream: it is all held now.
      this.fetched += received;
      if (received > 0 && seconds > 0) this.measured.push([received, seconds]);
      return { parts: [{ offset: 0, bytes: body }], total: received, whole: true, complete, received };
    }
    const type = response.headers.get('Content-Type') ?? '';
    const boundary = /multipart\/byteranges;\s*boundary="?([^";]+)"?/i.exec(type)?.[1];
    const parts = boundary ? parseMultipart(body, boundary)
      : [{ range: response.headers.get('Content-Range'), bytes: body }];
    const out = [];
    let total = 0, payload = 0;
    for (const p of parts) {
      const range = /^bytes (\d+)-(\d+)\/(\d+)$/.exec(p.range ?? '');
      if (!range) throw new FvvStreamError(`${this.url}: a range answer without a Content-Range`);
      total = Number(range[3]);
      const bytes = p.bytes.subarray(0, Number(range[2]) - Number(range[1]) + 1);
      if (bytes.length < Number(range[2]) - Number(range[1]) + 1) complete = false;
      out.push({ offset: Number(range[1]), bytes });
      payload += bytes.length;
    }
    // Every byte that came counts, the multipart's own lines too.
    this.fetched += received;
    if (payload > 0 && seconds > 0) this.measured.push([received, seconds]);
    return { parts: out, total, whole: false, complete, received };
  }

  async #call(method, ...args) {
    try {
      return await this.decoder[method](...args);
    } catch (e) {
      throw new FvvStreamError(`${this.url}: ${e.message}`);
    }
  }

  async #openHead(headBytes) {
    const first = await this.#get(0, headBytes);
    await this.#call('openRanges', first.total);
    await this.#call('addRange', 0, first.bytes);
    if (first.whole) {
      this.wholeFile = true;
      this.notice('the server does not answer Range requests: the whole stream was fetched');
    }
    for (let guard = 0; ; ++guard) {
      const event = await this.#call('process');
      if (event !== 'need') break;
      const want = await this.#call('wantedRange');
      if (!want || guard > 1000) throw new FvvStreamError(`${this.url}: the stream's head never completes`);
      const part = await this.#get(want.offset, want.size);
      if (part.bytes.length === 0) throw new FvvStreamError(`${this.url}: the stream ends before its head does`);
      await this.#call('addRange', want.offset, part.bytes);
    }
    this.info = await this.#call('info');
    // What the first decodes will hold, readied while the first GOP comes:
    // two GOPs (one shown, one decoded next) of the five cameras a view of
    // a ring decodes at most, about 10 bytes a texel (coefficients, YUV,
    // RGB), as measured on the sample stream. A worker's own call.
    const i = this.info;
    this.decoder.warmMemory?.(2 * i.gopFrames * Math.min(i.cameraCount, 5) * i.atlasWidth *
                              i.atlasHeight * 10)?.catch(() => {});
    this.groups = Math.ceil(this.info.cameraCount / this.info.gopCameras);
    this.gopSeconds = this.info.gopFrames / this.info.frameRate;
    // Where each fragment is, from the index, once: later fetches ask the
    // decoder nothing (it may be busy decoding). `held` is kept here.
    this.fragmentList = await this.#call('fragments', 0, await this.#call('fragmentCount'));
  }

  // The fragments of GOP `span` for `cameras` (indices; all when absent):
  // camera group 0 always (it carries the motion).
  fragmentsFor(span, cameras) {
    const groups = new Set([0]);
    for (const c of cameras ?? [...Array(this.info.cameraCount).keys()]) {
      groups.add(Math.floor(c / this.info.gopCameras));
    }
    return [...groups].sort((a, b) => a - b).map((g) => {
      const f = this.fragmentList[span * this.groups + g];
      if (!f) throw new FvvStreamError(`${this.url}: no fragment for GOP ${span}, camera group ${g}`);
      return f;
    });
  }

  // Fetches GOP `span` for `cameras`: each fragment's prefix as the fetch plan
  // gives it for `budget` bytes (default: what the bandwidth allows while a
  // GOP plays; unmeasured, whole fragments), the requests together. Returns
  // { fetched, parts, cameras, seconds, whole }: the bytes fetched, of
  // `cameras` those whose fragments hold their heads (they decode), the time
  // from the request to the last byte, and whether the plan took every
  // fragment whole. The bytes reach the decoder with addParts(parts), which a
  // player may leave until the decoder is free, fetching on meanwhile.
  // `planner` (FvvPlayback, on the page's thread) plans without waiting for
  // the decoder. Calls may overlap (GOPs of different spans).
  async fetchGopBytes(span, cameras, budget, planner = this.decoder) {
    if (this.wholeFile) return { fetched: 0, parts: [], seconds: 0, whole: true };
    const fragments = this.fragmentsFor(span, cameras);
    if (budget === undefined) {
      for (const [bytes, seconds] of this.measured.splice(0)) {
        this.bandwidth = await this.#call('bandwidthAfter', this.bandwidth, bytes, seconds);
      }
    }
    const allowed = budget ?? (this.bandwidth > 0
      ? await this.#call('gopFetchBudget', this.bandwidth, this.gopSeconds) : Number.MAX_SAFE_INTEGER);
    // Camera group 0's surface (it decodes whole or not at all), where this
    // GOP's size is not known: as large as the last one decoded (surfaceLearned).
    const plan = await planner.planPrefixes(fragments.map((f) => ({
      headSize: f.headSize, size: f.size,
      surfaceSize: f.surfaceSize || (f.firstCamera === 0 ? this.surfaceBytes ?? 0 : 0),
    })), allowed);
    const whole = fragments.every((f, i) => plan[i] >= f.size);
    const wanted = fragments.map((f, i) => [f, plan[i] - f.held]).filter(([, want]) => want > 0);
    const started = performance.now();
    let got = { parts: [], complete: true, whole: false, received: 0 };
    if (wanted.length > 0) {
      // One request for the GOP, however many fragments: a request costs a
      // round trip and its headers, more than a fragment's prefix at times.
      got = await this.#getRanges(wanted.map(([f, want]) => [f.offset + f.held, want]));
    }
    const seconds = (performance.now() - started) / 1000;
    if (got.whole) {
      this.wholeFile = true;
      for (const f of this.fragmentList) f.held = f.size;
      this.notice('the server answered a request for several ranges with the whole stream: it is all held now');
    }
    // Every byte that came, the multipart's own lines included.
    const fetched = got.received;
    const parts = got.parts.filter((p) => p.bytes.length > 0);
    for (const [f, want] of wanted) {
      // What the fragment holds now: the bytes from its start on, without a gap.
      const before = f.held;
      for (const p of parts) {
        const end = p.offset + p.bytes.length;
        if (p.offset <= f.offset + f.held && end > f.offset + f.held) {
          f.held = Math.min(f.size, end - f.offset);
        }
      }
      if (f.held - before < want) {
        this.notice(`the connection closed ${f.held - before} of ${want} bytes into fragment ` +
                    `${f.index}: it decodes from what arrived`);
      }
    }
    // The cameras whose fragments decode: each needs its head (a connection
    // that closed before the head left its camera out); the motion's too.
    const decodable = new Set(fragments.filter((f) => f.held >= f.headSize).map((f) => f.firstCamera));
    if (!decodable.has(0)) {  // fragments[0] is camera group 0's, which carries the motion
      throw new FvvStreamError(`${this.url}: GOP ${span}'s motion did not arrive (camera group 0's head)`);
    }
    const all = cameras ?? [...Array(this.info.cameraCount).keys()];
    const ready = all.filter((c) => decodable.has(c - (c % this.info.gopCameras)));
    return { fetched, parts, cameras: ready, seconds, whole };
  }

  // A decoded frame's surface size (decodeFrame's surfaceBytes): the estimate
  // for the next GOPs' fetch plans.
  surfaceLearned(frame) {
    if (frame?.surfaceBytes > 0) this.surfaceBytes = frame.surfaceBytes;
  }

  async addParts(parts) {
    if (parts.length > 0) await this.#call('addRanges', parts.map((p) => [p.offset, p.bytes]));
  }

  // fetchGopBytes, its bytes given to the decoder: returns the bytes fetched.
  async fetchGop(span, cameras, budget) {
    const { fetched, parts } = await this.fetchGopBytes(span, cameras, budget);
    await this.addParts(parts);
    return fetched;
  }

  // Decodes frame `index` for `cameras`; by default, the cameras whose
  // fragments of its GOP hold their heads (what arrived, verified, decodes).
  async frame(index, cameras) {
    const span = Math.floor(index / this.info.gopFrames);
    const fragments = this.wholeFile ? [] : this.fragmentsFor(span);
    const arrived = this.wholeFile ? undefined : [...Array(this.info.cameraCount).keys()].filter((c) => {
      const f = fragments.find((x) => x.firstCamera === c - (c % this.info.gopCameras));
      return f && f.held >= f.headSize;
    });
    const decoded = await this.#call('decodeFrame', index, { cameras: cameras ?? arrived });
    this.surfaceLearned(decoded);
    return decoded;
  }
}
