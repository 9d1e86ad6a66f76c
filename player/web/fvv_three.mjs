// The actor of an fvv stream as a three.js object: add it to a scene, move it
// like any Object3D, and three.js's render() draws it with Renderer II (the
// page's FvvRenderer in three's own WebGL 2 context, depth-tested against the
// scene), playing as the page's player plays (FvvPlayer: the module's loop,
// the stream by HTTP ranges, decoding in workers).
//
//   import * as THREE from 'three';
//   import { FvvActor } from './fvv_three.mjs';
//   const actor = await FvvActor.load(THREE, renderer, 'take.fvv');
//   scene.add(actor);
//   renderer.setAnimationLoop(() => renderer.render(scene, camera));
//   actor.player.pause(); actor.player.seek(40); actor.dispose();
//
// three.js comes from the page (passed in), so this module imports none.

import { FvvPlayer } from './fvv_player.mjs';

export class FvvActor {
  // THREE: the page's three.js module; renderer: its THREE.WebGLRenderer (a
  // WebGL 2 context); options: FvvPlayer's (prepared, autoplay, loop, ...).
  // Resolves to the actor's Object3D (a Mesh three.js never draws itself:
  // its onBeforeRender draws the actor), with .player and .dispose().
  static async load(THREE, renderer, url, options = {}) {
    const gl = renderer.getContext();
    if (!(typeof WebGL2RenderingContext !== 'undefined' && gl instanceof WebGL2RenderingContext)) {
      throw new Error('FvvActor needs a three.js renderer on WebGL 2');
    }
    const player = await FvvPlayer.open(gl.canvas, url, { ...options, gl });
    // One invisible triangle: what makes three.js call onBeforeRender where
    // the actor stands in the scene's order of drawing.
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute([0, 0, 0, 0, 0, 0, 0, 0, 0], 3));
    const material = new THREE.MeshBasicMaterial({ colorWrite: false, depthWrite: false });
    const mesh = new THREE.Mesh(geometry, material);
    mesh.name = 'fvv actor';
    mesh.frustumCulled = false;
    mesh.player = player;
    const eye = new THREE.Vector3(), local = new THREE.Vector3(), size = new THREE.Vector2();
    let last = performance.now();
    mesh.onBeforeRender = (r, scene, camera) => {
      const now = performance.now();
      const dt = Math.min(0.25, (now - last) / 1000);
      last = now;
      // The viewer in the stream's world: the camera seen from the actor.
      camera.getWorldPosition(eye);
      local.copy(eye).applyMatrix4(mesh.matrixWorld.clone().invert());
      if (!player.update(dt, local.toArray(), player.renderer.actor ?? [0, 1, 0])) return;
      r.getDrawingBufferSize(size);
      const target = r.getRenderTarget();
      // The framebuffer three.js is drawing into (a render target's, or the canvas).
      const framebuffer = gl.getParameter(gl.FRAMEBUFFER_BINDING);
      player.drawInto({
        eye: eye.toArray(),
        viewMatrix: new Float32Array(camera.matrixWorldInverse.elements),
        projection: new Float32Array(camera.projectionMatrix.elements),
      }, target ? target.width : size.x, target ? target.height : size.y, {
        framebuffer, model: new Float32Array(mesh.matrixWorld.elements),
      });
      // three.js keeps a copy of the GL state: it must read it afresh.
      r.resetState();
    };
    mesh.dispose = () => {
      player.destroy();
      geometry.dispose();
      material.dispose();
    };
    return mesh;
  }
}
