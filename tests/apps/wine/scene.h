/* What the Wine test programs share (d3d9.c, d3d11.c): the scene (four cubes at different
 * depths, a checkered ground), its camera in Direct3D's conventions, the HUD's place, a window,
 * and the screenshot file. Both programs draw the same picture with their own API. */
#ifndef HOLOINJECT_WINE_SCENE_H
#define HOLOINJECT_WINE_SCENE_H
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct { float m[4][4]; } mat4;
typedef struct { float x, y, z; DWORD c; } vertex;
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

/* The scene's camera: world, view and projection as a Direct3D program sets them. */
static const float EYE[3] = {0.5f, 3.0f, -9.0f}, AT[3] = {0.5f, 1.2f, 4.0f};
#define FOVY 0.9f
#define ZNEAR 0.5f
#define ZFAR 100.0f

/* The HUD, in window pixels (top-left origin): a bar and a square in the top-left corner. */
static void hud_rects(UINT width, UINT height, float bar[4], float square[4])
{
    const float hx = 16, hy = 16, hw = width / 4.0f, hh = height / 16.0f;
    bar[0] = hx, bar[1] = hy, bar[2] = hx + hw, bar[3] = hy + hh;
    square[0] = hx, square[1] = hy + 2 * hh, square[2] = hx + hh, square[3] = hy + 3 * hh;
}

/* A binary PPM (P6), top row first, of `h` rows of `pitch` bytes holding 4 bytes a pixel,
 * red at byte `red` (2 for BGRA, 0 for RGBA). */
static void write_ppm(const char *path, UINT w, UINT h, const BYTE *pixels, UINT pitch, int red)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        fprintf(stderr, "probe: cannot write %s\n", path);
        exit(1);
    }
    fprintf(f, "P6\n%u %u\n255\n", w, h);
    for (UINT y = 0; y < h; y++) {
        const BYTE *row = pixels + y * pitch;
        for (UINT x = 0; x < w; x++) {
            BYTE rgb[3] = {row[4 * x + red], row[4 * x + 1], row[4 * x + 2 - red]};
            fwrite(rgb, 1, 3, f);
        }
    }
    fclose(f);
}

/* A shown window whose client area is `w`x`h`. */
static HWND open_window(const char *title, UINT w, UINT h)
{
    HINSTANCE inst = GetModuleHandleA(NULL);
    WNDCLASSA wc = {0};
    wc.lpfnWndProc = DefWindowProcA;
    wc.hInstance = inst;
    wc.lpszClassName = title;
    RegisterClassA(&wc);
    RECT r = {0, 0, (LONG)w, (LONG)h};
    AdjustWindowRect(&r, WS_OVERLAPPEDWINDOW, FALSE);
    HWND wnd = CreateWindowA(wc.lpszClassName, title, WS_OVERLAPPEDWINDOW, 0, 0, r.right - r.left, r.bottom - r.top,
                             NULL, NULL, inst, NULL);
    if (!wnd) die("CreateWindow", (HRESULT)GetLastError());
    ShowWindow(wnd, SW_SHOW);
    return wnd;
}

static void pump_messages(void)
{
    MSG msg;
    while (PeekMessageA(&msg, NULL, 0, 0, PM_REMOVE)) {
        TranslateMessage(&msg);
        DispatchMessageA(&msg);
    }
}

/* Common arguments: --size WxH, --frames N, --screenshot out.ppm; `extra` takes the program's
 * own flags (returns 0 for an unknown one). */
typedef struct { UINT width, height; int frames; const char *shot; } options;

static options parse_options(int argc, char **argv, int (*extra)(const char *), const char *usage)
{
    options o = {640, 480, 5, NULL};
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--frames") && i + 1 < argc) o.frames = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--size") && i + 1 < argc) {
            if (sscanf(argv[++i], "%ux%u", &o.width, &o.height) != 2 || !o.width || !o.height) {
                fprintf(stderr, "probe: --size takes WxH, got %s\n", argv[i]);
                exit(2);
            }
        } else if (!strcmp(argv[i], "--screenshot") && i + 1 < argc) o.shot = argv[++i];
        else if (!extra(argv[i])) {
            fprintf(stderr, "probe: unknown argument %s\nusage: %s\n", argv[i], usage);
            exit(2);
        }
    }
    if (o.frames < 1) o.frames = 1;
    return o;
}
#endif
