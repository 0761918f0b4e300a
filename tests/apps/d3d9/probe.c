/* A Direct3D 9 program for the layer's Wine tests: four cubes at different depths, a checkered
 * ground and a pre-transformed HUD, drawn either with the fixed-function pipeline or with a
 * vs_2_0 vertex shader that applies the matrix as four dot products with constant rows (what
 * most Direct3D 9 games do, and what wined3d turns into `vs_c[]` uniforms). Both variants
 * draw the same picture. Under Wine, wined3d translates it all into OpenGL.
 *
 *   probe.exe [--shader | --world] [--size WxH] [--frames N] [--screenshot out.ppm]
 *
 * The scene is static, so every frame is the same picture; --screenshot writes the last
 * frame's back buffer (binary PPM, top row first) before it is presented: the program's own
 * picture, read without the layer. Built with x86_64-w64-mingw32-gcc (see build.sh). */
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#include <d3d9.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct { float m[4][4]; } mat4;
typedef struct { float x, y, z; DWORD c; } vertex;
typedef struct { float x, y, z, rhw; DWORD c; } hud_vertex;

#define SCENE_FVF (D3DFVF_XYZ | D3DFVF_DIFFUSE)
#define HUD_FVF (D3DFVF_XYZRHW | D3DFVF_DIFFUSE)
#define MAX_VERTICES 20000

static vertex scene[MAX_VERTICES];
static int scene_count;

static void die(const char *what, HRESULT hr)
{
    fprintf(stderr, "probe: %s failed (0x%08lx)\n", what, (unsigned long)hr);
    exit(1);
}

static DWORD shade(DWORD rgb, float f)
{
    int r = (int)(((rgb >> 16) & 255) * f), g = (int)(((rgb >> 8) & 255) * f), b = (int)((rgb & 255) * f);
    return 0xff000000u | (DWORD)(r << 16) | (DWORD)(g << 8) | (DWORD)b;
}

static void quad(const float p[4][3], DWORD c)
{
    static const int order[6] = {0, 1, 2, 0, 2, 3};
    for (int i = 0; i < 6 && scene_count < MAX_VERTICES; i++) {
        vertex *v = &scene[scene_count++];
        v->x = p[order[i]][0];
        v->y = p[order[i]][1];
        v->z = p[order[i]][2];
        v->c = c;
    }
}

/* A cube of half-size h at (x, y, z) whose faces are split into a 4x4 checker of two shades of
 * its colour (texture for the tests' block matching), lit by a fixed direction. */
static void cube(float x, float y, float z, float h, DWORD rgb)
{
    static const float normal[6][3] = {{0, 0, -1}, {0, 0, 1}, {-1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    const float light[3] = {-0.4f, 0.8f, -0.45f};
    for (int f = 0; f < 6; f++) {
        const float *n = normal[f];
        /* Two axes spanning the face: u horizontal, v = n x u. */
        float u[3] = {n[1] != 0 ? 1.0f : -n[2], 0, n[0]}, v[3];
        v[0] = n[1] * u[2] - n[2] * u[1];
        v[1] = n[2] * u[0] - n[0] * u[2];
        v[2] = n[0] * u[1] - n[1] * u[0];
        float lit = 0.35f + 0.65f * fmaxf(0.0f, n[0] * light[0] + n[1] * light[1] + n[2] * light[2]);
        for (int i = 0; i < 4; i++) {
            for (int j = 0; j < 4; j++) {
                float a0 = -h + 2 * h * i / 4, a1 = -h + 2 * h * (i + 1) / 4;
                float b0 = -h + 2 * h * j / 4, b1 = -h + 2 * h * (j + 1) / 4;
                float p[4][3];
                float ab[4][2] = {{a0, b0}, {a0, b1}, {a1, b1}, {a1, b0}};
                for (int k = 0; k < 4; k++)
                    for (int d = 0; d < 3; d++)
                        p[k][d] = (d == 0 ? x : d == 1 ? y : z) + n[d] * h + u[d] * ab[k][0] + v[d] * ab[k][1];
                quad((const float(*)[3])p, shade(rgb, lit * ((i + j) % 2 ? 1.0f : 0.7f)));
            }
        }
    }
}

static void build_scene(void)
{
    /* The ground: y = 0, a checker of 1-unit squares from z = -6 to 40. */
    for (int i = -10; i < 10; i++) {
        for (int k = -6; k < 40; k++) {
            float p[4][3] = {{(float)i, 0, (float)k}, {(float)i, 0, (float)k + 1}, {(float)i + 1, 0, (float)k + 1}, {(float)i + 1, 0, (float)k}};
            quad((const float(*)[3])p, (i + k) & 1 ? 0xff6b8e4eu : 0xff3f5a2eu);
        }
    }
    cube(-2.2f, 0.8f, -2.5f, 0.8f, 0xd04030); /* nearest */
    cube(1.2f, 1.0f, 2.0f, 1.0f, 0x3070d0);
    cube(-1.0f, 1.5f, 8.0f, 1.5f, 0xd0b030);
    cube(4.0f, 2.5f, 20.0f, 2.5f, 0xa040c0); /* farthest */
}

static mat4 mul(mat4 a, mat4 b)
{
    mat4 r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            r.m[i][j] = 0;
            for (int k = 0; k < 4; k++)
                r.m[i][j] += a.m[i][k] * b.m[k][j];
        }
    return r;
}

/* D3DXMatrixLookAtLH and D3DXMatrixPerspectiveFovLH (row vectors: v' = v * M). */
static mat4 look_at(const float eye[3], const float at[3])
{
    float z[3] = {at[0] - eye[0], at[1] - eye[1], at[2] - eye[2]};
    float zl = sqrtf(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    for (int i = 0; i < 3; i++) z[i] /= zl;
    float x[3] = {z[2], 0, -z[0]}; /* up (0,1,0) x z */
    float xl = sqrtf(x[0] * x[0] + x[2] * x[2]);
    x[0] /= xl; x[2] /= xl;
    float y[3] = {z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
    mat4 m = {{{x[0], y[0], z[0], 0}, {x[1], y[1], z[1], 0}, {x[2], y[2], z[2], 0},
               {-(x[0] * eye[0] + x[1] * eye[1] + x[2] * eye[2]), -(y[0] * eye[0] + y[1] * eye[1] + y[2] * eye[2]),
                -(z[0] * eye[0] + z[1] * eye[1] + z[2] * eye[2]), 1}}};
    return m;
}

static mat4 perspective(float fovy, float aspect, float zn, float zf)
{
    float ys = 1.0f / tanf(fovy / 2), xs = ys / aspect;
    mat4 m = {{{xs, 0, 0, 0}, {0, ys, 0, 0}, {0, 0, zf / (zf - zn), 1}, {0, 0, -zn * zf / (zf - zn), 0}}};
    return m;
}

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
    FILE *f = fopen(path, "wb");
    if (!f) {
        fprintf(stderr, "probe: cannot write %s\n", path);
        exit(1);
    }
    fprintf(f, "P6\n%u %u\n255\n", w, h);
    for (UINT y = 0; y < h; y++) {
        const BYTE *row = (const BYTE *)lr.pBits + y * lr.Pitch;
        for (UINT x = 0; x < w; x++) {
            BYTE rgb[3] = {row[4 * x + 2], row[4 * x + 1], row[4 * x]};
            fwrite(rgb, 1, 3, f);
        }
    }
    fclose(f);
    IDirect3DSurface9_UnlockRect(sys);
    IDirect3DSurface9_Release(sys);
    IDirect3DSurface9_Release(back);
}

int main(int argc, char **argv)
{
    int use_shader = 0, world = 0, frames = 5;
    UINT width = 640, height = 480;
    const char *shot = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--shader")) use_shader = 1;
        else if (!strcmp(argv[i], "--world")) use_shader = world = 1;
        else if (!strcmp(argv[i], "--frames") && i + 1 < argc) frames = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--size") && i + 1 < argc) {
            if (sscanf(argv[++i], "%ux%u", &width, &height) != 2 || !width || !height) {
                fprintf(stderr, "probe: --size takes WxH, got %s\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(argv[i], "--screenshot") && i + 1 < argc) shot = argv[++i];
        else {
            fprintf(stderr, "probe: unknown argument %s\nusage: probe.exe [--shader | --world] [--size WxH] [--frames N] [--screenshot out.ppm]\n", argv[i]);
            return 2;
        }
    }
    if (frames < 1) frames = 1;

    HINSTANCE inst = GetModuleHandleA(NULL);
    WNDCLASSA wc = {0};
    wc.lpfnWndProc = DefWindowProcA;
    wc.hInstance = inst;
    wc.lpszClassName = "holoinject-d3d9-probe";
    RegisterClassA(&wc);
    RECT r = {0, 0, (LONG)width, (LONG)height};
    AdjustWindowRect(&r, WS_OVERLAPPEDWINDOW, FALSE);
    HWND wnd = CreateWindowA(wc.lpszClassName, "d3d9 probe", WS_OVERLAPPEDWINDOW, 0, 0, r.right - r.left,
                             r.bottom - r.top, NULL, NULL, inst, NULL);
    if (!wnd) die("CreateWindow", (HRESULT)GetLastError());
    ShowWindow(wnd, SW_SHOW);

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
    const float eye[3] = {0.5f, 3.0f, -9.0f}, at[3] = {0.5f, 1.2f, 4.0f};
    mat4 view = look_at(eye, at);
    mat4 proj = perspective(0.9f, (float)width / (float)height, 0.5f, 100.0f);
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
    /* The HUD: a bar and a square in the top-left corner, in screen pixels. */
    const float hx = 16, hy = 16, hw = width / 4.0f, hh = height / 16.0f;
    hud_vertex hud[12] = {
        {hx, hy, 0, 1, 0xffffffff}, {hx + hw, hy, 0, 1, 0xffffffff}, {hx + hw, hy + hh, 0, 1, 0xffe0e0e0},
        {hx, hy, 0, 1, 0xffffffff}, {hx + hw, hy + hh, 0, 1, 0xffe0e0e0}, {hx, hy + hh, 0, 1, 0xffe0e0e0},
        {hx, hy + 2 * hh, 0, 1, 0xff20d0d0}, {hx + hh, hy + 2 * hh, 0, 1, 0xff20d0d0}, {hx + hh, hy + 3 * hh, 0, 1, 0xff108080},
        {hx, hy + 2 * hh, 0, 1, 0xff20d0d0}, {hx + hh, hy + 3 * hh, 0, 1, 0xff108080}, {hx, hy + 3 * hh, 0, 1, 0xff108080},
    };

    for (int frame = 0; frame < frames; frame++) {
        MSG msg;
        while (PeekMessageA(&msg, NULL, 0, 0, PM_REMOVE)) {
            TranslateMessage(&msg);
            DispatchMessageA(&msg);
        }
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
        if (shot && frame == frames - 1) screenshot(dev, shot, width, height);
        hr = IDirect3DDevice9_Present(dev, NULL, NULL, NULL, NULL);
        if (FAILED(hr)) die("Present", hr);
    }
    if (vs) IDirect3DVertexShader9_Release(vs);
    IDirect3DDevice9_Release(dev);
    IDirect3D9_Release(d3d);
    DestroyWindow(wnd);
    return 0;
}
