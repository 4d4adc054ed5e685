// Compile check of the Unreal include (glslangValidator's HLSL front end): what a Custom node's
// body does, inside a pixel shader.
#include "NdfmipVmf.ush"

float4 main(float4 a : TEXCOORD0, float4 b : TEXCOORD1, float3 l : TEXCOORD2, float3 v : TEXCOORD3) : SV_Target
{
    return float4(NdfmipVmfGgx4(a, b, b, a, normalize(l), normalize(v), float3(0.5f, 0.5f, 0.5f), 0.1f, float3(1.0f, 1.0f, 1.0f)), 1.0f);
}
