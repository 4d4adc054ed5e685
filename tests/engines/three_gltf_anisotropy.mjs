// Loads ?glb= (ndfmip gltf --method sggx) with three.js's GLTFLoader and KTX2Loader and reports
// what three made of KHR_materials_anisotropy: the material's type and anisotropy, its
// anisotropyMap (where it came from, its levels, level 1 read back from the GPU with texelFetch
// into an RGBA8 target), and the quad rendered under a directional light twice, as loaded and
// with anisotropy 0, with the mean absolute difference of the two images. POSTs the report to
// /result (or the error to /fail).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { KTX2Loader } from 'three/addons/loaders/KTX2Loader.js';

import { fail, levelFetchQuad, post } from './page_report.mjs';

const kSize = 64; // the rendered images, kSize²

// Level `level` of `texture`, exactly: each texel fetched into an RGBA8 target of its size.
function readLevel(renderer, texture, level) {
    const { width, height } = texture.mipmaps[level];
    const target = new THREE.WebGLRenderTarget(width, height, { depthBuffer: false });
    const scene = new THREE.Scene();
    scene.add(levelFetchQuad(texture, level));
    renderer.setRenderTarget(target);
    renderer.render(scene, new THREE.OrthographicCamera());
    const pixels = new Uint8Array(4 * width * height);
    renderer.readRenderTargetPixels(target, 0, 0, width, height, pixels);
    renderer.setRenderTarget(null);
    target.dispose();
    // The mean of each of R, G, B over the level (it is uniform: each texel averages one
    // stripe of each tilt).
    const mean = [0, 0, 0];
    for (let i = 0; i < width * height; ++i)
        for (let c = 0; c < 3; ++c) mean[c] += pixels[4 * i + c] / (width * height);
    return { width, height, mean };
}

// The glTF scene into an RGBA8 target, kSize², as bytes.
function render(renderer, scene, camera) {
    const target = new THREE.WebGLRenderTarget(kSize, kSize);
    renderer.setRenderTarget(target);
    renderer.render(scene, camera);
    const pixels = new Uint8Array(4 * kSize * kSize);
    renderer.readRenderTargetPixels(target, 0, 0, kSize, kSize, pixels);
    renderer.setRenderTarget(null);
    target.dispose();
    return pixels;
}

async function main() {
    const params = new URLSearchParams(location.search);
    const canvas = document.createElement('canvas');
    canvas.width = canvas.height = kSize;
    document.body.appendChild(canvas);
    const renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
    const gl = renderer.getContext();
    const ktx2 = new KTX2Loader()
        .setTranscoderPath('/three/examples/jsm/libs/basis/')
        .detectSupport(renderer);
    const gltf = await new GLTFLoader().setKTX2Loader(ktx2).loadAsync(params.get('glb'));
    let mesh = null;
    gltf.scene.traverse(o => { if (o.isMesh && !mesh) mesh = o; });
    if (!mesh) throw new Error('no mesh in the GLB');
    const material = mesh.material;
    const map = material.anisotropyMap;
    const report = {
        three: THREE.REVISION,
        type: material.type,
        anisotropy: material.anisotropy,
        anisotropyRotation: material.anisotropyRotation,
        roughness: material.roughness,
        anisotropyMap: map ? {
            mimeType: map.userData.mimeType || null,
            compressed: !!map.isCompressedTexture,
            generateMipmaps: map.generateMipmaps,
            mipmaps: map.mipmaps.length,
            level1: readLevel(renderer, map, 1),
        } : null,
    };

    // The quad (tangent along x, where the stripes spread the normals) seen from below its -y
    // edge, lit from beyond its +y edge and off to +x: the half vectors lean along x, where the
    // anisotropic lobe (alpha_t) reaches and the isotropic one (alpha_b) does not. The light is
    // dim enough that the highlight does not clip at 255.
    gltf.scene.updateMatrixWorld(true);
    const box = new THREE.Box3().setFromObject(mesh);
    const centre = box.getCenter(new THREE.Vector3());
    const camera = new THREE.PerspectiveCamera(50, 1, 0.05, 100);
    camera.position.copy(centre).add(new THREE.Vector3(0, -1.2, 1.5));
    camera.lookAt(centre);
    const light = new THREE.DirectionalLight(0xffffff, 1);
    light.position.set(0.8, 1.2, 1.5);
    gltf.scene.add(light);
    const loaded = render(renderer, gltf.scene, camera);
    material.anisotropy = 0;
    const isotropic = render(renderer, gltf.scene, camera);
    let difference = 0, brightness = 0;
    for (let i = 0; i < kSize * kSize; ++i)
        for (let c = 0; c < 3; ++c) {
            difference += Math.abs(loaded[4 * i + c] - isotropic[4 * i + c]);
            brightness += loaded[4 * i + c];
        }
    report.meanDifference = difference / (3 * kSize * kSize);
    report.meanBrightness = brightness / (3 * kSize * kSize);
    report.glError = gl.getError();
    await post('/result', report);
}

main().catch(fail);
