// ---- wrappers.hlsl: the lobe sum, for shaders and for Shader Graph.

// J = 4 lobes (`ndfmip bake --method vmf --lobes 4`): each lobe's texel (alpha, alpha r mu) as
// sampled from lobe<j>.ktx2, l and v unit vectors towards the light and the viewer in the
// surface's tangent frame (z the geometric normal, x the texture's u direction, y = z x x).
// Reflected radiance per unit irradiance: multiply by the light's colour (and by 1/d^2 for a
// point light), not by n.l, which it carries.
float3 ndfmipShadeVmfLobes4(NdfmipMaterial m, float3 albedo, float4 lobe0, float4 lobe1, float4 lobe2, float4 lobe3,
                            float3 l, float3 v)
{
    return ndfmipShadeVmfLobe(m, albedo, lobe0, l, v) + ndfmipShadeVmfLobe(m, albedo, lobe1, l, v)
         + ndfmipShadeVmfLobe(m, albedo, lobe2, l, v) + ndfmipShadeVmfLobe(m, albedo, lobe3, l, v);
}

// Shader Graph's Custom Function node (Type File, Name NdfmipVmfGgx4): GGX of alpha Alpha (not
// perceptual roughness) with specular colour Specular.
void NdfmipVmfGgx4_float(float4 Lobe0, float4 Lobe1, float4 Lobe2, float4 Lobe3, float3 L, float3 V, float3 Albedo,
                         float Alpha, float3 Specular, out float3 Out)
{
    NdfmipMaterial m;
    m.brdf = NDFMIP_GGX;
    m.exponent = 0.0f;
    m.roughness = Alpha;
    m.specular = Specular;
    Out = ndfmipShadeVmfLobes4(m, Albedo, Lobe0, Lobe1, Lobe2, Lobe3, L, V);
}
