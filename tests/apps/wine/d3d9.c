/* A Direct3D 9 program for the layer's Wine tests: four cubes at different depths, a checkered
 * ground and a pre-transformed HUD, drawn either with the fixed-function pipeline or with a
 * vs_2_0 vertex shader that applies the matrix as four dot products with constant rows (what
 * most Direct3D 9 games do, and what wined3d turns into `vs_c[]` uniforms). Both variants
 * draw the same picture. Under Wine, wined3d translates it all into OpenGL.
 *
 *   d3d9.exe [--shader | --world] [--size WxH] [--frames N] [--screenshot out.ppm]
 *
 * The scene is static, so every frame is the same picture; --screenshot writes the last
 * frame's back buffer (binary PPM, top row first) before it is presented: the program's own
 * picture, read without the layer. Built with x86_64-w64-mingw32-gcc (tests/integration/wine.rs). */
#include "scene.h"
#include <d3d9.h>

typedef struct { float x, y, z, rhw; DWORD c; } hud_vertex;

#define SCENE_FVF (D3DFVF_XYZ | D3DFVF_DIFFUSE)
#define HUD_FVF (D3DFVF_XYZRHW | D3DFVF_DIFFUSE)

/* vs_2_0: dcl_position v0; dcl_color v1; dp4 oPos.x..w, v0, c0..c3; mov oD0, v1. With
 * --world, also dp4 oT0.x..w, v0, c4..c7 (a world position handed on, as lit shaders do): two
 * matrices in the constants, and nothing tells which one is the projection. */
static const DWORD vertex_shader[] = {
    0xfffe0200,
    0x0200001f, 0x80000000, 0x900f0000,
    0x0200001f, 0x8000000a, 0x900f0001,
    0x03000009, 0xc0010000, 0x90e40000, 0xa0e40000,
    0x03000009, 0xc0020000, 0x90e40000, 0xa0e40001,
    0x03000009, 0xc0040000, 0x90e40000, 0xa0e40002,
    0x03000009, 0xc0080000, 0x90e40000, 0xa0e40003,
    0x02000001, 0xd00f0000, 0x90e40001,
    0x0000ffff,
};

static const DWORD world_shader[] = {
    0xfffe0200,
    0x0200001f, 0x80000000, 0x900f0000,
    0x0200001f, 0x8000000a, 0x900f0001,
    0x03000009, 0xe0010000, 0x90e40000, 0xa0e40004,
    0x03000009, 0xe0020000, 0x90e40000, 0xa0e40005,
    0x03000009, 0xe0040000, 0x90e40000, 0xa0e40006,
    0x03000009, 0xe0080000, 0x90e40000, 0xa0e40007,
    0x03000009, 0xc0010000, 0x90e40000, 0xa0e40000,
    0x03000009, 0xc0020000, 0x90e40000, 0xa0e40001,
    0x03000009, 0xc0040000, 0x90e40000, 0xa0e40002,
    0x03000009, 0xc0080000, 0x90e40000, 0xa0e40003,
    0x02000001, 0xd00f0000, 0x90e40001,
    0x0000ffff,
};

static void screenshot(IDirect3DDevice9 *dev, const char *path, UINT w, UINT h)
{
    IDirect3DSurface9 *back, *sys;
    HRESULT hr = IDirect3DDevice9_GetBackBuffer(dev, 0, 0, D3DBACKBUFFER_TYPE_MONO, &back);
    if (FAILED(hr)) die("GetBackBuffer", hr);
    hr = IDirect3DDevice9_CreateOffscreenPlainSurface(dev, w, h, D3DFMT_X8R8G8B8, D3DPOOL_SYSTEMMEM, &sys, NULL);
    if (FAILED(hr)) die("CreateOffscreenPlainSurface", hr);
    hr = IDirect3DDevice9_GetRenderTargetData(dev, back, sys);
    if (FAILED(hr)) die("GetRenderTargetData", hr);
    D3DLOCKED_RECT lr;
    hr = IDirect3DSurface9_LockRect(sys, &lr, NULL, D3DLOCK_READONLY);
    if (FAILED(hr)) die("LockRect", hr);
    write_ppm(path, w, h, (const BYTE *)lr.pBits, (UINT)lr.Pitch, 2);
    IDirect3DSurface9_UnlockRect(sys);
    IDirect3DSurface9_Release(sys);
    IDirect3DSurface9_Release(back);
}

static int use_shader, world;

static int variant(const char *arg)
{
    if (!strcmp(arg, "--shader")) return use_shader = 1;
    if (!strcmp(arg, "--world")) return use_shader = world = 1;
    return 0;
}

int main(int argc, char **argv)
{
    options o = parse_options(argc, argv, variant,
                              "d3d9.exe [--shader | --world] [--size WxH] [--frames N] [--screenshot out.ppm]");
    UINT width = o.width, height = o.height;
    HWND wnd = open_window("d3d9 probe", width, height);

    IDirect3D9 *d3d = Direct3DCreate9(D3D_SDK_VERSION);
    if (!d3d) die("Direct3DCreate9", E_FAIL);
    D3DPRESENT_PARAMETERS pp = {0};
    pp.Windowed = TRUE;
    pp.SwapEffect = D3DSWAPEFFECT_DISCARD;
    pp.BackBufferWidth = width;
    pp.BackBufferHeight = height;
    pp.BackBufferFormat = D3DFMT_X8R8G8B8;
    pp.EnableAutoDepthStencil = TRUE;
    pp.AutoDepthStencilFormat = D3DFMT_D24S8;
    pp.PresentationInterval = D3DPRESENT_INTERVAL_IMMEDIATE;
    pp.hDeviceWindow = wnd;
    IDirect3DDevice9 *dev;
    HRESULT hr = IDirect3D9_CreateDevice(d3d, D3DADAPTER_DEFAULT, D3DDEVTYPE_HAL, wnd,
                                         D3DCREATE_HARDWARE_VERTEXPROCESSING, &pp, &dev);
    if (FAILED(hr)) die("CreateDevice", hr);

    build_scene();
    mat4 view = look_at(EYE, AT);
    mat4 proj = perspective(FOVY, (float)width / (float)height, ZNEAR, ZFAR);
    mat4 identity = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
    mat4 wvp = mul(view, proj);
    float rows[4][4]; /* transpose(wvp): c_i . v = column i of v * WVP */
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            rows[i][j] = wvp.m[j][i];

    IDirect3DVertexShader9 *vs = NULL;
    if (use_shader) {
        hr = IDirect3DDevice9_CreateVertexShader(dev, world ? world_shader : vertex_shader, &vs);
        if (FAILED(hr)) die("CreateVertexShader", hr);
    }
    float bar[4], sq[4];
    hud_rects(width, height, bar, sq);
    hud_vertex hud[12] = {
        {bar[0], bar[1], 0, 1, 0xffffffff}, {bar[2], bar[1], 0, 1, 0xffffffff}, {bar[2], bar[3], 0, 1, 0xffe0e0e0},
        {bar[0], bar[1], 0, 1, 0xffffffff}, {bar[2], bar[3], 0, 1, 0xffe0e0e0}, {bar[0], bar[3], 0, 1, 0xffe0e0e0},
        {sq[0], sq[1], 0, 1, 0xff20d0d0}, {sq[2], sq[1], 0, 1, 0xff20d0d0}, {sq[2], sq[3], 0, 1, 0xff108080},
        {sq[0], sq[1], 0, 1, 0xff20d0d0}, {sq[2], sq[3], 0, 1, 0xff108080}, {sq[0], sq[3], 0, 1, 0xff108080},
    };

    for (int frame = 0; frame < o.frames; frame++) {
        pump_messages();
        IDirect3DDevice9_Clear(dev, 0, NULL, D3DCLEAR_TARGET | D3DCLEAR_ZBUFFER, 0xff8fb8e0, 1.0f, 0);
        IDirect3DDevice9_BeginScene(dev);
        IDirect3DDevice9_SetRenderState(dev, D3DRS_LIGHTING, FALSE);
        IDirect3DDevice9_SetRenderState(dev, D3DRS_CULLMODE, D3DCULL_NONE);
        IDirect3DDevice9_SetRenderState(dev, D3DRS_ZENABLE, D3DZB_TRUE);
        IDirect3DDevice9_SetFVF(dev, SCENE_FVF);
        if (use_shader) {
            IDirect3DDevice9_SetVertexShader(dev, vs);
            IDirect3DDevice9_SetVertexShaderConstantF(dev, 0, &rows[0][0], 4);
            IDirect3DDevice9_SetVertexShaderConstantF(dev, 4, &identity.m[0][0], 4);
        } else {
            IDirect3DDevice9_SetTransform(dev, D3DTS_WORLD, (const D3DMATRIX *)&identity);
            IDirect3DDevice9_SetTransform(dev, D3DTS_VIEW, (const D3DMATRIX *)&view);
            IDirect3DDevice9_SetTransform(dev, D3DTS_PROJECTION, (const D3DMATRIX *)&proj);
        }
        IDirect3DDevice9_DrawPrimitiveUP(dev, D3DPT_TRIANGLELIST, scene_count / 3, scene, sizeof(vertex));
        IDirect3DDevice9_SetVertexShader(dev, NULL);
        IDirect3DDevice9_SetRenderState(dev, D3DRS_ZENABLE, D3DZB_FALSE);
        IDirect3DDevice9_SetFVF(dev, HUD_FVF);
        IDirect3DDevice9_DrawPrimitiveUP(dev, D3DPT_TRIANGLELIST, 4, hud, sizeof(hud_vertex));
        IDirect3DDevice9_EndScene(dev);
        if (o.shot && frame == o.frames - 1) screenshot(dev, o.shot, width, height);
        hr = IDirect3DDevice9_Present(dev, NULL, NULL, NULL, NULL);
        if (FAILED(hr)) die("Present", hr);
    }
    if (vs) IDirect3DVertexShader9_Release(vs);
    IDirect3DDevice9_Release(dev);
    IDirect3D9_Release(d3d);
    DestroyWindow(wnd);
    return 0;
}
