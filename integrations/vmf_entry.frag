// A caller of the vMF shading library, so that its SPIR-V (and spirv-cross's HLSL and GLSL ES
// translations of it) holds every function an engine needs; integrations/CMakeLists.txt keeps
// the functions and drops this entry point and its uniforms.
uniform NdfmipMaterial ndfmipMaterial;
uniform vec3 ndfmipAlbedo;
uniform vec4 ndfmipLobeTexel;
uniform vec3 ndfmipL;
uniform vec3 ndfmipV;
layout(location = 0) out vec4 ndfmipColour;

void main() {
    vec3 shaded = ndfmipShadeVmfLobe(ndfmipMaterial, ndfmipAlbedo, ndfmipLobeTexel, ndfmipL, ndfmipV);
    NdfmipLobe lobe = ndfmipUnpackLobe(ndfmipLobeTexel);
    ndfmipColour = vec4(shaded, ndfmipVmfWidenedAlpha(ndfmipMaterial.roughness, lobe.kappa));
}
