/* A Direct3D 11 program for the layer's Wine tests: the scene of d3d9.c (four cubes at
 * different depths, a checkered ground, a HUD in the top-left corner), drawn with HLSL
 * shaders compiled at run time: the scene's matrix in a constant buffer (row_major, row
 * vectors, as Direct3D programs keep it), the HUD's vertices given in clip space. Under Wine,
 * wined3d's Direct3D 10/11 path translates it into OpenGL (shader model 4 to GLSL, constant
 * buffers to uniform blocks): a different route from the Direct3D 9 program's.
 *
 *   d3d11.exe [--size WxH] [--frames N] [--screenshot out.ppm]
 *
 * The scene is static; --screenshot writes the last frame's back buffer (binary PPM, top row
 * first) before it is presented. Built with x86_64-w64-mingw32-gcc (tests/integration/wine.rs):
 * -ld3d11 -ld3dcompiler -ldxguid. */
#define COBJMACROS
#include "scene.h"
#include <d3d11.h>
#include <d3dcompiler.h>

static const char HLSL[] =
    "cbuffer camera : register(b0) { row_major float4x4 wvp; };\n"
    "struct vs_in { float3 pos : POSITION; float4 col : COLOR; };\n"
    "struct vs_out { float4 pos : SV_Position; float4 col : COLOR; };\n"
    "vs_out scene_vs(vs_in v) { vs_out o; o.pos = mul(float4(v.pos, 1.0), wvp); o.col = v.col; return o; }\n"
    "vs_out hud_vs(vs_in v) { vs_out o; o.pos = float4(v.pos, 1.0); o.col = v.col; return o; }\n"
    "float4 colour_ps(vs_out i) : SV_Target { return i.col; }\n";

static ID3DBlob *compile(const char *entry, const char *target)
{
    ID3DBlob *code = NULL, *errors = NULL;
    HRESULT hr = D3DCompile(HLSL, sizeof(HLSL) - 1, "probe.hlsl", NULL, NULL, entry, target, 0, 0, &code, &errors);
    if (FAILED(hr)) {
        fprintf(stderr, "probe: %s: %s\n", entry, errors ? (const char *)ID3D10Blob_GetBufferPointer(errors) : "");
        die("D3DCompile", hr);
    }
    if (errors) ID3D10Blob_Release(errors);
    return code;
}

static ID3D11Buffer *buffer(ID3D11Device *dev, UINT bind, const void *data, UINT bytes)
{
    D3D11_BUFFER_DESC desc = {0};
    desc.ByteWidth = bytes;
    desc.Usage = D3D11_USAGE_DEFAULT;
    desc.BindFlags = bind;
    D3D11_SUBRESOURCE_DATA init = {data, 0, 0};
    ID3D11Buffer *b;
    HRESULT hr = ID3D11Device_CreateBuffer(dev, &desc, &init, &b);
    if (FAILED(hr)) die("CreateBuffer", hr);
    return b;
}

static void screenshot(ID3D11Device *dev, ID3D11DeviceContext *ctx, ID3D11Texture2D *back, const char *path)
{
    D3D11_TEXTURE2D_DESC desc;
    ID3D11Texture2D_GetDesc(back, &desc);
    desc.Usage = D3D11_USAGE_STAGING;
    desc.BindFlags = 0;
    desc.CPUAccessFlags = D3D11_CPU_ACCESS_READ;
    desc.MiscFlags = 0;
    ID3D11Texture2D *staging;
    HRESULT hr = ID3D11Device_CreateTexture2D(dev, &desc, NULL, &staging);
    if (FAILED(hr)) die("CreateTexture2D (staging)", hr);
    ID3D11DeviceContext_CopyResource(ctx, (ID3D11Resource *)staging, (ID3D11Resource *)back);
    D3D11_MAPPED_SUBRESOURCE map;
    hr = ID3D11DeviceContext_Map(ctx, (ID3D11Resource *)staging, 0, D3D11_MAP_READ, 0, &map);
    if (FAILED(hr)) die("Map", hr);
    write_ppm(path, desc.Width, desc.Height, (const BYTE *)map.pData, map.RowPitch, 0);
    ID3D11DeviceContext_Unmap(ctx, (ID3D11Resource *)staging, 0);
    ID3D11Texture2D_Release(staging);
}

static int no_flags(const char *arg)
{
    (void)arg;
    return 0;
}

int main(int argc, char **argv)
{
    options o = parse_options(argc, argv, no_flags, "d3d11.exe [--size WxH] [--frames N] [--screenshot out.ppm]");
    UINT width = o.width, height = o.height;
    HWND wnd = open_window("d3d11 probe", width, height);

    DXGI_SWAP_CHAIN_DESC sd = {0};
    sd.BufferDesc.Width = width;
    sd.BufferDesc.Height = height;
    sd.BufferDesc.Format = DXGI_FORMAT_R8G8B8A8_UNORM;
    sd.SampleDesc.Count = 1;
    sd.BufferUsage = DXGI_USAGE_RENDER_TARGET_OUTPUT;
    sd.BufferCount = 1;
    sd.OutputWindow = wnd;
    sd.Windowed = TRUE;
    sd.SwapEffect = DXGI_SWAP_EFFECT_DISCARD;
    const D3D_FEATURE_LEVEL levels[] = {D3D_FEATURE_LEVEL_11_0, D3D_FEATURE_LEVEL_10_1, D3D_FEATURE_LEVEL_10_0};
    IDXGISwapChain *chain;
    ID3D11Device *dev;
    ID3D11DeviceContext *ctx;
    D3D_FEATURE_LEVEL level;
    HRESULT hr = D3D11CreateDeviceAndSwapChain(NULL, D3D_DRIVER_TYPE_HARDWARE, NULL, 0, levels, 3, D3D11_SDK_VERSION, &sd,
                                               &chain, &dev, &level, &ctx);
    if (FAILED(hr)) die("D3D11CreateDeviceAndSwapChain", hr);

    ID3D11Texture2D *back;
    hr = IDXGISwapChain_GetBuffer(chain, 0, &IID_ID3D11Texture2D, (void **)&back);
    if (FAILED(hr)) die("GetBuffer", hr);
    ID3D11RenderTargetView *rtv;
    hr = ID3D11Device_CreateRenderTargetView(dev, (ID3D11Resource *)back, NULL, &rtv);
    if (FAILED(hr)) die("CreateRenderTargetView", hr);
    D3D11_TEXTURE2D_DESC dd = {0};
    dd.Width = width;
    dd.Height = height;
    dd.MipLevels = 1;
    dd.ArraySize = 1;
    dd.Format = DXGI_FORMAT_D24_UNORM_S8_UINT;
    dd.SampleDesc.Count = 1;
    dd.Usage = D3D11_USAGE_DEFAULT;
    dd.BindFlags = D3D11_BIND_DEPTH_STENCIL;
    ID3D11Texture2D *depth;
    hr = ID3D11Device_CreateTexture2D(dev, &dd, NULL, &depth);
    if (FAILED(hr)) die("CreateTexture2D (depth)", hr);
    ID3D11DepthStencilView *dsv;
    hr = ID3D11Device_CreateDepthStencilView(dev, (ID3D11Resource *)depth, NULL, &dsv);
    if (FAILED(hr)) die("CreateDepthStencilView", hr);

    ID3DBlob *scene_code = compile("scene_vs", "vs_4_0"), *hud_code = compile("hud_vs", "vs_4_0");
    ID3DBlob *ps_code = compile("colour_ps", "ps_4_0");
    ID3D11VertexShader *scene_vs, *hud_vs;
    ID3D11PixelShader *ps;
    hr = ID3D11Device_CreateVertexShader(dev, ID3D10Blob_GetBufferPointer(scene_code), ID3D10Blob_GetBufferSize(scene_code),
                                         NULL, &scene_vs);
    if (FAILED(hr)) die("CreateVertexShader (scene)", hr);
    hr = ID3D11Device_CreateVertexShader(dev, ID3D10Blob_GetBufferPointer(hud_code), ID3D10Blob_GetBufferSize(hud_code),
                                         NULL, &hud_vs);
    if (FAILED(hr)) die("CreateVertexShader (hud)", hr);
    hr = ID3D11Device_CreatePixelShader(dev, ID3D10Blob_GetBufferPointer(ps_code), ID3D10Blob_GetBufferSize(ps_code), NULL,
                                        &ps);
    if (FAILED(hr)) die("CreatePixelShader", hr);
    /* The vertex's colour is a D3DCOLOR (0xAARRGGBB, little-endian: B, G, R, A bytes). */
    const D3D11_INPUT_ELEMENT_DESC layout_desc[] = {
        {"POSITION", 0, DXGI_FORMAT_R32G32B32_FLOAT, 0, 0, D3D11_INPUT_PER_VERTEX_DATA, 0},
        {"COLOR", 0, DXGI_FORMAT_B8G8R8A8_UNORM, 0, 12, D3D11_INPUT_PER_VERTEX_DATA, 0},
    };
    ID3D11InputLayout *layout;
    hr = ID3D11Device_CreateInputLayout(dev, layout_desc, 2, ID3D10Blob_GetBufferPointer(scene_code),
                                        ID3D10Blob_GetBufferSize(scene_code), &layout);
    if (FAILED(hr)) die("CreateInputLayout", hr);

    D3D11_RASTERIZER_DESC rd = {0};
    rd.FillMode = D3D11_FILL_SOLID;
    rd.CullMode = D3D11_CULL_NONE;
    rd.DepthClipEnable = TRUE;
    ID3D11RasterizerState *raster;
    hr = ID3D11Device_CreateRasterizerState(dev, &rd, &raster);
    if (FAILED(hr)) die("CreateRasterizerState", hr);
    D3D11_DEPTH_STENCIL_DESC zd = {0};
    zd.DepthEnable = TRUE;
    zd.DepthWriteMask = D3D11_DEPTH_WRITE_MASK_ALL;
    zd.DepthFunc = D3D11_COMPARISON_LESS;
    ID3D11DepthStencilState *ztest, *zoff;
    hr = ID3D11Device_CreateDepthStencilState(dev, &zd, &ztest);
    if (FAILED(hr)) die("CreateDepthStencilState", hr);
    zd.DepthEnable = FALSE;
    zd.DepthWriteMask = D3D11_DEPTH_WRITE_MASK_ZERO;
    hr = ID3D11Device_CreateDepthStencilState(dev, &zd, &zoff);
    if (FAILED(hr)) die("CreateDepthStencilState", hr);

    build_scene();
    mat4 wvp = mul(look_at(EYE, AT), perspective(FOVY, (float)width / (float)height, ZNEAR, ZFAR));
    ID3D11Buffer *scene_vb = buffer(dev, D3D11_BIND_VERTEX_BUFFER, scene, scene_count * sizeof(vertex));
    ID3D11Buffer *camera = buffer(dev, D3D11_BIND_CONSTANT_BUFFER, &wvp, sizeof(wvp));
    /* The HUD's rectangles in clip space (x right, y up, z 0: in front of everything). */
    float bar[4], sq[4];
    hud_rects(width, height, bar, sq);
#define CX(px) (2.0f * (px) / width - 1.0f)
#define CY(py) (1.0f - 2.0f * (py) / height)
    vertex hud[12] = {
        {CX(bar[0]), CY(bar[1]), 0, 0xffffffff}, {CX(bar[2]), CY(bar[1]), 0, 0xffffffff}, {CX(bar[2]), CY(bar[3]), 0, 0xffe0e0e0},
        {CX(bar[0]), CY(bar[1]), 0, 0xffffffff}, {CX(bar[2]), CY(bar[3]), 0, 0xffe0e0e0}, {CX(bar[0]), CY(bar[3]), 0, 0xffe0e0e0},
        {CX(sq[0]), CY(sq[1]), 0, 0xff20d0d0},   {CX(sq[2]), CY(sq[1]), 0, 0xff20d0d0},   {CX(sq[2]), CY(sq[3]), 0, 0xff108080},
        {CX(sq[0]), CY(sq[1]), 0, 0xff20d0d0},   {CX(sq[2]), CY(sq[3]), 0, 0xff108080},   {CX(sq[0]), CY(sq[3]), 0, 0xff108080},
    };
    ID3D11Buffer *hud_vb = buffer(dev, D3D11_BIND_VERTEX_BUFFER, hud, sizeof(hud));

    D3D11_VIEWPORT vp = {0, 0, (float)width, (float)height, 0, 1};
    const float sky[4] = {0x8f / 255.0f, 0xb8 / 255.0f, 0xe0 / 255.0f, 1.0f};
    const UINT stride = sizeof(vertex), offset = 0;
    for (int frame = 0; frame < o.frames; frame++) {
        pump_messages();
        ID3D11DeviceContext_OMSetRenderTargets(ctx, 1, &rtv, dsv);
        ID3D11DeviceContext_ClearRenderTargetView(ctx, rtv, sky);
        ID3D11DeviceContext_ClearDepthStencilView(ctx, dsv, D3D11_CLEAR_DEPTH | D3D11_CLEAR_STENCIL, 1.0f, 0);
        ID3D11DeviceContext_RSSetViewports(ctx, 1, &vp);
        ID3D11DeviceContext_RSSetState(ctx, raster);
        ID3D11DeviceContext_IASetInputLayout(ctx, layout);
        ID3D11DeviceContext_IASetPrimitiveTopology(ctx, D3D11_PRIMITIVE_TOPOLOGY_TRIANGLELIST);
        ID3D11DeviceContext_PSSetShader(ctx, ps, NULL, 0);

        ID3D11DeviceContext_OMSetDepthStencilState(ctx, ztest, 0);
        ID3D11DeviceContext_VSSetShader(ctx, scene_vs, NULL, 0);
        ID3D11DeviceContext_VSSetConstantBuffers(ctx, 0, 1, &camera);
        ID3D11DeviceContext_IASetVertexBuffers(ctx, 0, 1, &scene_vb, &stride, &offset);
        ID3D11DeviceContext_Draw(ctx, scene_count, 0);

        ID3D11DeviceContext_OMSetDepthStencilState(ctx, zoff, 0);
        ID3D11DeviceContext_VSSetShader(ctx, hud_vs, NULL, 0);
        ID3D11DeviceContext_IASetVertexBuffers(ctx, 0, 1, &hud_vb, &stride, &offset);
        ID3D11DeviceContext_Draw(ctx, 12, 0);

        if (o.shot && frame == o.frames - 1) screenshot(dev, ctx, back, o.shot);
        hr = IDXGISwapChain_Present(chain, 0, 0);
        if (FAILED(hr)) die("Present", hr);
    }
    ID3D11DeviceContext_ClearState(ctx);
    ID3D11DeviceContext_Release(ctx);
    ID3D11Device_Release(dev);
    IDXGISwapChain_Release(chain);
    DestroyWindow(wnd);
    return 0;
}
