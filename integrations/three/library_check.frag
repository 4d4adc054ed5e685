// Compile check of the GLSL the three.js module embeds, as GLSL ES 3.00 (WebGL2's language;
// the library's text comes first).
uniform NdfmipMaterial m;
uniform vec4 lobe;
uniform vec3 l;
uniform vec3 v;
out vec4 colour;

void main() {
    NdfmipLobe unpacked = ndfmipUnpackLobe(lobe);
    colour = vec4(ndfmipShadeVmfLobe(m, vec3(0.5f), lobe, l, v), ndfmipVmfWidenedAlpha(m.roughness, unpacked.kappa));
}
