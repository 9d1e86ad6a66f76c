// Renderer II in WebGL 2 (player/render/renderer.h in the browser): the body
// model skinned in the decoded pose, each fragment blending the camera
// textures by viewing angle and facing, each camera's visibility from the
// stream's masks or, without masks, from its depth map of the posed model.
// The shaders are the native renderer's files (player/render/shaders, copied
// beside the module by the build), given GLSL ES 3.00's header; the constants,
// the choice of cameras and the simplified body the depth maps draw come from
// the module (FvvPlayback), which runs the native player's code.
//
//   const r = await FvvRenderer.create(gl, { shaderUrl, model, cameras, info, playback });
//   // depthTriangles: the simplified body already made (FvvDecoder.depthMapTriangles,
//   // in a worker); else the renderer makes it with `playback` when a frame
//   // without masks first needs depth maps.
//   r.setFrame(frame);   // from FvvDecoder.decodeFrame (RGB)
//   r.draw(view, width, height);   // view: { viewMatrix, projection, eye }

import { cameraViewProjection, invert, multiply, transformPoint } from './fvv_view.mjs';

const MAX_CAMERAS = 64;
const DEPTH_NEAR = 0.05, DEPTH_FAR = 100;  // player/render/camera_depth_maps.cc
const NO_SURFACE = 1e9;
export const BACKGROUND = [0.12, 0.12, 0.14];

// A native GLSL 3.30 source as GLSL ES 3.00, with `defines` after the version.
function toEs(source, defines = '') {
  const body = source.slice(source.indexOf('\n') + 1);
  return '#version 300 es\nprecision highp float;\nprecision highp int;\n' +
    'precision highp sampler2DArray;\n' + defines + body;
}

function compile(gl, type, source, what) {
  const s = gl.createShader(type);
  gl.shaderSource(s, source);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) {
    throw new Error(`${what}: ${gl.getShaderInfoLog(s)}`);
  }
  return s;
}

// WebGL links no program without a fragment shader, even one that only
// captures vertices by transform feedback.
const NO_FRAGMENTS = '#version 300 es\nprecision mediump float;\nout vec4 o;\nvoid main() { o = vec4(0.0); }\n';

function program(gl, vertex, fragment, what, feedback) {
  const p = gl.createProgram();
  gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, vertex, what + ' (vertex)'));
  gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, fragment ?? NO_FRAGMENTS, what + ' (fragment)'));
  if (feedback) gl.transformFeedbackVaryings(p, [feedback], gl.SEPARATE_ATTRIBS);
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(`${what}: ${gl.getProgramInfoLog(p)}`);
  return p;
}

export class FvvRenderer {
  static async create(gl, { shaderUrl, model, cameras, info, playback, depthTriangles }) {
    const load = async (name) => {
      const r = await fetch(new URL(name, shaderUrl));
      if (!r.ok) throw new Error(`shader ${name}: ${r.status}`);
      return r.text();
    };
    const [skinning, blend, depthVert, depthFrag] = await Promise.all(
      ['skinning.vert', 'renderer.frag', 'camera_depth.vert', 'camera_depth.frag'].map(load));
    return new FvvRenderer(gl, { skinning, blend, depthVert, depthFrag }, model, cameras, info, playback,
      depthTriangles);
  }

  constructor(gl, src, model, cameras, info, playback, depthTriangles) {
    if (cameras.length === 0 || cameras.length > MAX_CAMERAS) {
      throw new Error(`the renderer takes 1 to 64 cameras, not ${cameras.length}`);
    }
    const bones = model.boneRestWorld.length / 16;
    if (bones > 256) throw new Error(`the renderer takes at most 256 bones, not ${bones}`);
    this.gl = gl;
    this.cameras = cameras;
    this.playback = playback;
    this.constants = playback.renderConstants();
    this.width = info.atlasWidth;
    this.height = info.atlasHeight;
    this.bones = bones;
    // One program per visibility source, as the native renderer builds them.
    this.maskProgram = program(gl, toEs(src.skinning), toEs(src.blend), 'renderer');
    this.depthProgram = program(gl, toEs(src.skinning),
      toEs(src.blend, '#define FVV_DEPTH_VISIBILITY 1\n'), 'renderer (depth maps)');
    this.mapProgram = program(gl, toEs(src.depthVert), toEs(src.depthFrag), 'camera depth maps');
    this.skinProgram = program(gl, toEs(src.skinning), null, 'skinning for depth maps', 'v_world');
    for (const p of [this.maskProgram, this.depthProgram, this.skinProgram]) {
      gl.uniformBlockBinding(p, gl.getUniformBlockIndex(p, 'Bones'), 0);
    }
    gl.uniformBlockBinding(this.depthProgram, gl.getUniformBlockIndex(this.depthProgram, 'DepthCameras'), 1);

    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const attribute = (location, data, size, integer, usage = gl.STATIC_DRAW) => {
      const b = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, data, usage);
      gl.enableVertexAttribArray(location);
      if (integer) gl.vertexAttribIPointer(location, size, gl.UNSIGNED_SHORT, 0, 0);
      else gl.vertexAttribPointer(location, size, gl.FLOAT, false, 0, 0);
      return b;
    };
    const joints = Uint16Array.from(model.joints, (j) => (j < bones ? j : 0));
    // Positions in a buffer of their own: a frame's surface (format version
    // 12) replaces the model's.
    this.modelPositions = model.positions;
    this.positions = attribute(0, model.positions, 3, false, gl.DYNAMIC_DRAW);
    this.positionsAreSurface = false;
    attribute(1, model.normals, 3);
    attribute(2, model.uvs, 2);
    attribute(3, joints, 4, true);
    attribute(4, model.weights, 4);
    const ibo = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ibo);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, model.triangles, gl.STATIC_DRAW);
    gl.bindVertexArray(null);
    this.vao = vao;
    this.indexCount = model.triangles.length;
    this.vertexCount = model.positions.length / 3;
    // The skinned positions the depth maps draw, and their vertex array (its
    // triangles, the simplified body, set when the depth maps are made).
    this.skinned = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, this.skinned);
    gl.bufferData(gl.ARRAY_BUFFER, this.vertexCount * 12, gl.DYNAMIC_COPY);
    this.skinnedVao = gl.createVertexArray();
    gl.bindVertexArray(this.skinnedVao);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 12, 0);
    gl.bindVertexArray(null);
    this.modelTriangles = model.triangles;
    this.depthTriangles = depthTriangles ?? null;
    gl.bindBuffer(gl.ARRAY_BUFFER, null);

    this.bonesUbo = gl.createBuffer();
    gl.bindBuffer(gl.UNIFORM_BUFFER, this.bonesUbo);
    gl.bufferData(gl.UNIFORM_BUFFER, 256 * 64, gl.DYNAMIC_DRAW);
    const array = (internal, format) => {
      const t = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, t);
      gl.texStorage3D(gl.TEXTURE_2D_ARRAY, 1, internal, this.width, this.height, cameras.length);
      gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
      gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
      gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
      gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
      return t;
    };
    this.textures = array(gl.RGB8, gl.RGB);
    this.masks = array(gl.R8, gl.RED);
    this.centres = new Float32Array(cameras.flatMap((c) => c.centre));
    this.present = [];
    this.hasFrame = false;
    this.depth = null;  // made on the first frame without masks
    this.depthMapMs = 0;
  }

  // Bone matrices, textures and masks of a decoded RGB frame. Cameras the
  // decode left out (null pixels) take no part in blending.
  setFrame(frame) {
    const gl = this.gl;
    if (frame.format !== 'rgb') throw new Error('the renderer takes RGB frames');
    if (frame.views.length !== this.cameras.length || frame.width !== this.width ||
        frame.height !== this.height || frame.boneSkin.length !== this.bones * 16) {
      throw new Error('the frame does not match the stream the renderer was made for');
    }
    gl.bindBuffer(gl.UNIFORM_BUFFER, this.bonesUbo);
    gl.bufferSubData(gl.UNIFORM_BUFFER, 0, frame.boneSkin);
    if (frame.surface || this.positionsAreSurface) {
      gl.bindBuffer(gl.ARRAY_BUFFER, this.positions);
      gl.bufferSubData(gl.ARRAY_BUFFER, 0, frame.surface ?? this.modelPositions);
      gl.bindBuffer(gl.ARRAY_BUFFER, null);
      this.positionsAreSurface = !!frame.surface;
    }
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    this.present = [];
    frame.views.forEach((v, c) => { if (v.pixels) this.present.push(c); });
    if (this.present.length === 0) throw new Error('the frame holds no camera\'s texture');
    this.hasMasks = frame.views[this.present[0]].mask !== null;
    for (const c of this.present) {
      const v = frame.views[c];
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.textures);
      gl.texSubImage3D(gl.TEXTURE_2D_ARRAY, 0, 0, 0, c, this.width, this.height, 1, gl.RGB,
        gl.UNSIGNED_BYTE, v.pixels);
      if (this.hasMasks) {
        const mask = v.mask.map((m) => (m ? 255 : 0));
        gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.masks);
        gl.texSubImage3D(gl.TEXTURE_2D_ARRAY, 0, 0, 0, c, this.width, this.height, 1, gl.RED,
          gl.UNSIGNED_BYTE, mask);
      }
    }
    this.actor = [frame.boneWorld[12], frame.boneWorld[13], frame.boneWorld[14]];
    this.depthRendered = new Set();
    this.hasFrame = true;
  }

  // view: { viewMatrix, projection (Float32Array(16), column-major), eye }.
  // Draws into `framebuffer` (the canvas by default), cleared to the
  // background first unless `clear` is false (a scene the actor joins, whose
  // depth it then tests against); `model` places the actor in that scene
  // (its world from the stream's). Returns the cameras it blended.
  draw(view, width, height, { exponent, facingExponent, clear = true, framebuffer = null, model } = {}) {
    if (!this.hasFrame) throw new Error('draw before setFrame');
    const gl = this.gl, k = this.constants;
    // The eye in the stream's world, where the cameras and the blend are.
    const eye = model ? transformPoint(invert(model), view.eye) : view.eye;
    // Of the cameras whose textures are here, those the view weighs
    // (player/playback/view_cameras.h, as the native renderer picks them).
    const blended = this.playback.viewCameras(this.present, eye, this.actor);
    if (!this.hasMasks) this.#renderDepthMaps(blended);
    gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
    gl.viewport(0, 0, width, height);
    if (clear) {
      gl.clearColor(...BACKGROUND, 1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    }
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LESS);
    // The body model is closed and wound counter-clockwise: its back faces
    // are hidden anyway, and a software rasteriser would shade them first
    // (40 % of the blend pass's time on SwiftShader; 0-2 pixels differ).
    gl.enable(gl.CULL_FACE);
    gl.cullFace(gl.BACK);
    const p = this.hasMasks ? this.maskProgram : this.depthProgram;
    gl.useProgram(p);
    const u = (name) => gl.getUniformLocation(p, name);
    gl.uniform1i(u('u_skinned'), 1);
    const viewProj = multiply(view.projection, view.viewMatrix);
    gl.uniformMatrix4fv(u('u_view_proj'), false, model ? multiply(viewProj, model) : viewProj);
    gl.uniform3fv(u('u_cameras'), this.centres);
    gl.uniform1i(u('u_view_camera_count'), blended.length);
    gl.uniform1iv(u('u_view_cameras'), Int32Array.from(blended.length ? blended : [0]));
    gl.uniform3fv(u('u_eye'), Float32Array.from(eye));
    gl.uniform1f(u('u_exponent'), exponent ?? k.viewExponent);
    gl.uniform1f(u('u_angle_epsilon'), k.angleEpsilon);
    gl.uniform1f(u('u_facing_exponent'), facingExponent ?? k.facingExponent);
    gl.uniform1i(u('u_textures'), 0);
    gl.uniform1i(u('u_masks'), 1);
    gl.uniform1i(u('u_depth'), 2);
    gl.uniform4f(u('u_visibility_rule'), k.depthTolerance, k.slopeTexels, k.minFacing, k.fullFacing);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.textures);
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.masks);
    if (!this.hasMasks) {
      gl.activeTexture(gl.TEXTURE2);
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.depth.texture);
      gl.bindBufferBase(gl.UNIFORM_BUFFER, 1, this.depth.block);
    }
    gl.bindBufferBase(gl.UNIFORM_BUFFER, 0, this.bonesUbo);
    gl.bindVertexArray(this.vao);
    gl.drawElements(gl.TRIANGLES, this.indexCount, gl.UNSIGNED_INT, 0);
    gl.bindVertexArray(null);
    gl.disable(gl.CULL_FACE);
    gl.activeTexture(gl.TEXTURE0);
    return blended;
  }

  // Each camera's depth map of the posed model (player/render/camera_depth_maps.h):
  // z along its optical axis, 1e9 where it sees no surface.
  #makeDepthMaps() {
    const gl = this.gl;
    if (!gl.getExtension('EXT_color_buffer_float')) {
      throw new Error('this browser cannot render to float textures (EXT_color_buffer_float): ' +
                      'a stream without masks needs it for its cameras\' depth maps');
    }
    let width = 0, height = 0;
    for (const c of this.cameras) {
      if (!c.width || !c.height || !(c.fx > 0) || !(c.fy > 0)) {
        throw new Error('a camera without an image size or focal length');
      }
      const [w, h] = this.playback.depthMapSize(c.width, c.height);
      width = Math.max(width, w);
      height = Math.max(height, h);
    }
    // std140: mat4 world_to_camera[64], vec4 projection[64], vec4 texel_angle[64].
    const block = new Float32Array(MAX_CAMERAS * 24);
    const viewProj = this.cameras.map((c, i) => {
      for (let r = 0; r < 3; ++r) {
        for (let k = 0; k < 3; ++k) block[i * 16 + k * 4 + r] = c.rotation[r * 3 + k];
        block[i * 16 + 12 + r] = c.translation[r];
      }
      block[i * 16 + 15] = 1;
      block.set([c.fx / c.width, c.fy / c.height, (c.cx + 0.5) / c.width, (c.cy + 0.5) / c.height],
        MAX_CAMERAS * 16 + i * 4);
      const texelsPerRadian = Math.min(c.fx * width / c.width, c.fy * height / c.height);
      block[MAX_CAMERAS * 20 + i * 4] = 1 / texelsPerRadian;
      const { viewMatrix, projection } = cameraViewProjection(c, DEPTH_NEAR, DEPTH_FAR);
      return multiply(projection, viewMatrix);
    });
    const texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, texture);
    gl.texStorage3D(gl.TEXTURE_2D_ARRAY, 1, gl.R32F, width, height, this.cameras.length);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
    const depthBuffer = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, depthBuffer);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, width, height);
    const framebuffer = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
    gl.framebufferTextureLayer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, texture, 0, 0);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depthBuffer);
    const status = gl.checkFramebufferStatus(gl.FRAMEBUFFER);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    if (status !== gl.FRAMEBUFFER_COMPLETE) {
      throw new Error(`depth maps: no R32F render target (framebuffer status ${status})`);
    }
    const ubo = gl.createBuffer();
    gl.bindBuffer(gl.UNIFORM_BUFFER, ubo);
    gl.bufferData(gl.UNIFORM_BUFFER, block, gl.STATIC_DRAW);
    // The simplified body (player/playback/depth_map_triangles.h, the native
    // renderer's triangles): given, or made now (a stream with masks never
    // needs it).
    const triangles = this.depthTriangles ??
      this.playback.depthMapTriangles(this.modelPositions, this.modelTriangles);
    gl.bindVertexArray(this.skinnedVao);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, gl.createBuffer());
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, triangles, gl.STATIC_DRAW);
    gl.bindVertexArray(null);
    this.depthIndexCount = triangles.length;
    this.depthTriangles = this.modelTriangles = null;
    this.depth = { texture, framebuffer, block: ubo, width, height, viewProj };
  }

  #renderDepthMaps(cameras) {
    const needed = cameras.filter((c) => !this.depthRendered.has(c));
    if (needed.length === 0) return;
    if (!this.depth) this.#makeDepthMaps();
    const gl = this.gl, d = this.depth;
    const t0 = performance.now();
    // Skin every vertex once, into `skinned`.
    gl.useProgram(this.skinProgram);
    gl.uniform1i(gl.getUniformLocation(this.skinProgram, 'u_skinned'), 1);
    gl.bindBufferBase(gl.UNIFORM_BUFFER, 0, this.bonesUbo);
    gl.bindBufferBase(gl.TRANSFORM_FEEDBACK_BUFFER, 0, this.skinned);
    gl.bindVertexArray(this.vao);
    gl.enable(gl.RASTERIZER_DISCARD);
    gl.beginTransformFeedback(gl.POINTS);
    gl.drawArrays(gl.POINTS, 0, this.vertexCount);
    gl.endTransformFeedback();
    gl.disable(gl.RASTERIZER_DISCARD);
    gl.bindBufferBase(gl.TRANSFORM_FEEDBACK_BUFFER, 0, null);
    // Each camera's pass draws the skinned vertices.
    gl.bindFramebuffer(gl.FRAMEBUFFER, d.framebuffer);
    gl.viewport(0, 0, d.width, d.height);
    gl.useProgram(this.mapProgram);
    const viewProj = gl.getUniformLocation(this.mapProgram, 'u_view_proj');
    gl.bindVertexArray(this.skinnedVao);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LESS);
    gl.depthMask(true);
    gl.enable(gl.CULL_FACE);  // the nearest surface of a closed model faces the camera
    gl.cullFace(gl.BACK);
    const far = new Float32Array([NO_SURFACE, NO_SURFACE, NO_SURFACE, NO_SURFACE]);
    for (const c of needed) {
      gl.framebufferTextureLayer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, d.texture, 0, c);
      gl.clearBufferfv(gl.COLOR, 0, far);
      gl.clearBufferfv(gl.DEPTH, 0, new Float32Array([1]));
      gl.uniformMatrix4fv(viewProj, false, d.viewProj[c]);
      gl.drawElements(gl.TRIANGLES, this.depthIndexCount, gl.UNSIGNED_INT, 0);
      this.depthRendered.add(c);
    }
    gl.bindVertexArray(null);
    gl.disable(gl.CULL_FACE);
    this.depthMapMs += performance.now() - t0;
  }

  // The default framebuffer as top-down RGB8 (a screenshot's pixels).
  readRgb(width, height) {
    const gl = this.gl, rgba = new Uint8Array(width * height * 4);
    gl.pixelStorei(gl.PACK_ALIGNMENT, 1);
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, rgba);
    const rgb = new Uint8Array(width * height * 3);
    for (let y = 0; y < height; ++y) {
      for (let x = 0; x < width; ++x) {
        const s = ((height - 1 - y) * width + x) * 4, t = (y * width + x) * 3;
        rgb[t] = rgba[s];
        rgb[t + 1] = rgba[s + 1];
        rgb[t + 2] = rgba[s + 2];
      }
    }
    return rgb;
  }
}
