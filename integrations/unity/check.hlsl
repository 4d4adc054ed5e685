// Compile check of the Unity include (glslangValidator's HLSL front end): a pixel shader that
// calls the Shader Graph function.
#include "ndfmip_vmf.hlsl"

float4 main(float4 a : TEXCOORD0, float4 b : TEXCOORD1, float3 l : TEXCOORD2, float3 v : TEXCOORD3) : SV_Target
{
    float3 shaded;
    NdfmipVmfGgx4_float(a, b, b, a, normalize(l), normalize(v), float3(0.5f, 0.5f, 0.5f), 0.1f, float3(1.0f, 1.0f, 1.0f), shaded);
    return float4(shaded, 1.0f);
}
