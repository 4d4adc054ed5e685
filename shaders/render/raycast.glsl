// ndfmip's GPU renderer: the scene's camera, object and material as uniforms (set by
// src/gpu/gpu_renderer.cpp), which render/ray_geometry.glsl, next, traces per pixel: the CPU
// renderer's own source (src/render/geometry.cpp), so a GPU image can be compared with the CPU's.

uniform NdfmipMaterial ndfmipMaterial;
uniform vec3 ndfmipMaterialAlbedo; // the material's albedo (an albedo map multiplies it)

uniform int ndfmipCameraType; // 0 perspective, 1 orthographic
uniform vec3 ndfmipEye;
uniform vec3 ndfmipForward;
uniform vec3 ndfmipRight;
uniform vec3 ndfmipUp;
uniform vec2 ndfmipHalfSize;  // half the image plane: at distance 1 (perspective) or in world units
uniform vec2 ndfmipImageSize; // pixels

uniform int ndfmipGeometryType; // 0 plane, 1 sphere
uniform vec3 ndfmipCenter;
uniform vec3 ndfmipNormal;
uniform vec3 ndfmipTangent;
uniform vec2 ndfmipPlaneSize;
uniform vec2 ndfmipTiling;
uniform float ndfmipRadius;
