// An engine's geometric specular anti-aliasing in the GPU renderer (RenderOptions::
// specularAntiAliasing, ndfmipSpecularAaKernel in brdf.glsl): main.frag sets each lookup's kernel
// here, and the glue of the single-lobe shaders (render/naive.glsl, render/roughness_mips.glsl,
// which ggx-fit reads too, and render/ggx_aniso.glsl) widens its lobe by it.
uniform float ndfmipSpecularAaVariance; // 0: off
uniform float ndfmipSpecularAaThreshold;
float ndfmipAaKernel = 0.0f; // this lookup's (0: none)
