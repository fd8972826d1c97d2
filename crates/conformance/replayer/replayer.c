/*
 * replayer: executes pointillist call streams on a real IDirect3DDevice9 and writes what the
 * device drew. The stream format and this program's inputs and outputs are specified in
 * docs/CONFORMANCE.md; pointillist's `conform` command runs it and compares the images.
 *
 *   replayer OUTDIR CALLS...      (an argument @LIST reads stream paths from LIST, one a line)
 *
 * For each stream: a HAL device (hardware or software vertex processing as the stream's header
 * says) on a hidden window with an automatic D24S8 depth buffer (so D3DRS_ZENABLE defaults to
 * D3DZB_TRUE), an A8R8G8B8 render target of the stream's size, the stream's calls between BeginScene and EndScene, then GetRenderTargetData and
 * LockRect. Writes OUTDIR/NAME.png (RGBA8, the target's bytes, alpha included; NAME is the
 * stream's file name without its directory and its .calls extension), a line in
 * OUTDIR/results.txt per stream ("NAME<TAB>ok" or "NAME<TAB>error<TAB>what failed"), and
 * OUTDIR/device.txt (the adapter's identity and caps, key=value lines); OUTDIR is created when
 * missing. Every HRESULT is
 * checked: a failing call ends its stream with the call named, and the next stream goes on.
 * Exit status 0 when every stream was run (whatever their results), 2 when nothing could be.
 *
 * C99 and d3d9.h: x86_64-w64-mingw32-gcc -std=c99 -O2 -o replayer.exe replayer.c -ld3d9
 * (or i686-w64-mingw32-gcc, or MSVC: cl /O2 replayer.c d3d9.lib user32.lib).
 */
#define COBJMACROS
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#include <d3d9.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FORMAT_VERSION 1u
#define FLAG_SOFTWARE_VP 1u
#define NO_TEXTURE 0xFFFFFFFFu
#define MAX_TEXTURES 4096u

enum {
    OP_END = 0, OP_CLEAR, OP_RENDER_STATE, OP_TEXTURE_STAGE_STATE, OP_SAMPLER_STATE,
    OP_CREATE_TEXTURE, OP_SET_TEXTURE, OP_TRANSFORM, OP_VIEWPORT, OP_CLIP_PLANE,
    OP_DRAW_POINTS, OP_MATERIAL, OP_LIGHT, OP_LIGHT_ENABLE
};

/* ---- small helpers ---------------------------------------------------------------------- */

static uint32_t rd32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float rdf(const unsigned char *p)
{
    uint32_t u = rd32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static const char *hr_name(HRESULT hr)
{
    switch (hr) {
    case D3DERR_INVALIDCALL: return "D3DERR_INVALIDCALL";
    case D3DERR_NOTAVAILABLE: return "D3DERR_NOTAVAILABLE";
    case D3DERR_OUTOFVIDEOMEMORY: return "D3DERR_OUTOFVIDEOMEMORY";
    case D3DERR_DEVICELOST: return "D3DERR_DEVICELOST";
    case D3DERR_DRIVERINTERNALERROR: return "D3DERR_DRIVERINTERNALERROR";
    case D3DERR_WRONGTEXTUREFORMAT: return "D3DERR_WRONGTEXTUREFORMAT";
    case D3DERR_UNSUPPORTEDCOLOROPERATION: return "D3DERR_UNSUPPORTEDCOLOROPERATION";
    case D3DERR_UNSUPPORTEDALPHAOPERATION: return "D3DERR_UNSUPPORTEDALPHAOPERATION";
    case D3DERR_TOOMANYOPERATIONS: return "D3DERR_TOOMANYOPERATIONS";
    case E_OUTOFMEMORY: return "E_OUTOFMEMORY";
    case E_FAIL: return "E_FAIL";
    default: return "HRESULT";
    }
}

/* ---- PNG output: RGBA8, stored (uncompressed) deflate blocks ----------------------------- */

static uint32_t crc_table[256];

static void crc_init(void)
{
    uint32_t n, k, c;
    for (n = 0; n < 256; n++) {
        c = n;
        for (k = 0; k < 8; k++)
            c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        crc_table[n] = c;
    }
}

static uint32_t crc_update(uint32_t crc, const unsigned char *p, size_t n)
{
    while (n--)
        crc = crc_table[(crc ^ *p++) & 0xFF] ^ (crc >> 8);
    return crc;
}

static void put_be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

static int write_chunk(FILE *f, const char *type, const unsigned char *data, uint32_t len)
{
    unsigned char b[4];
    uint32_t crc;
    put_be32(b, len);
    if (fwrite(b, 1, 4, f) != 4 || fwrite(type, 1, 4, f) != 4)
        return 0;
    if (len && fwrite(data, 1, len, f) != len)
        return 0;
    crc = crc_update(0xFFFFFFFFu, (const unsigned char *)type, 4);
    crc = crc_update(crc, data, len) ^ 0xFFFFFFFFu;
    put_be32(b, crc);
    return fwrite(b, 1, 4, f) == 4;
}

/* Writes rgba (width * height * 4 bytes) as a PNG; returns 0 on failure. */
static int write_png(const char *path, uint32_t width, uint32_t height, const unsigned char *rgba)
{
    static const unsigned char sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    unsigned char ihdr[13];
    size_t row = (size_t)width * 4 + 1, raw_len = row * height, blocks, z_len, i, at = 0;
    unsigned char *z;
    uint32_t a = 1, b = 0;
    FILE *f;
    int ok;

    blocks = raw_len / 65535 + 1;
    z_len = 2 + raw_len + blocks * 5 + 4;
    z = (unsigned char *)malloc(z_len);
    if (!z)
        return 0;
    z[at++] = 0x78;
    z[at++] = 0x01;
    for (i = 0; i < blocks; i++) {
        size_t start = i * 65535, n = raw_len - start < 65535 ? raw_len - start : 65535, k;
        z[at++] = (unsigned char)(i + 1 == blocks);
        z[at++] = (unsigned char)n;
        z[at++] = (unsigned char)(n >> 8);
        z[at++] = (unsigned char)~n;
        z[at++] = (unsigned char)(~n >> 8);
        for (k = start; k < start + n; k++) {
            size_t y = k / row, x = k % row;
            unsigned char v = x == 0 ? 0 : rgba[y * (size_t)width * 4 + x - 1];
            z[at++] = v;
            a = (a + v) % 65521;
            b = (b + a) % 65521;
        }
    }
    put_be32(z + at, b << 16 | a);
    at += 4;

    put_be32(ihdr, width);
    put_be32(ihdr + 4, height);
    ihdr[8] = 8;  /* bit depth */
    ihdr[9] = 6;  /* RGBA */
    ihdr[10] = ihdr[11] = ihdr[12] = 0;
    f = fopen(path, "wb");
    if (!f) {
        free(z);
        return 0;
    }
    ok = fwrite(sig, 1, 8, f) == 8 && write_chunk(f, "IHDR", ihdr, 13) &&
         write_chunk(f, "IDAT", z, (uint32_t)at) && write_chunk(f, "IEND", NULL, 0);
    ok = fclose(f) == 0 && ok;
    free(z);
    return ok;
}

/* ---- one stream --------------------------------------------------------------------------- */

struct replay {
    IDirect3D9 *d3d;
    HWND window;
    D3DCAPS9 caps;
    char message[512];
};

#define FAIL(...) do { snprintf(r->message, sizeof r->message, __VA_ARGS__); goto done; } while (0)
#define CHECK(call, ...)                                                                      \
    do {                                                                                      \
        HRESULT hr_ = (call);                                                                 \
        if (FAILED(hr_)) {                                                                    \
            char what_[256];                                                                  \
            snprintf(what_, sizeof what_, __VA_ARGS__);                                       \
            FAIL("%s failed: %s (0x%08lX), record at byte %lu", what_, hr_name(hr_),         \
                 (unsigned long)hr_, (unsigned long)at);                                      \
        }                                                                                     \
    } while (0)

/* Replays one stream; returns 1 and fills rgba (width * height * 4) on success, else 0 with
 * r->message saying what failed. */
static int replay(struct replay *r, const unsigned char *s, size_t len, uint32_t *out_w,
                  uint32_t *out_h, unsigned char **out_rgba)
{
    IDirect3DDevice9 *dev = NULL;
    IDirect3DSurface9 *rt = NULL, *sys = NULL;
    IDirect3DTexture9 **textures = NULL;
    D3DPRESENT_PARAMETERS pp;
    D3DLOCKED_RECT lr;
    unsigned char *rgba = NULL;
    uint32_t width, height, flags, x, y;
    size_t at = 0;
    int ok = 0, in_scene = 0;

    r->message[0] = 0;
    if (len < 24 || memcmp(s, "PTLCALLS", 8) != 0)
        FAIL("not a call stream (no PTLCALLS header)");
    if (rd32(s + 8) != FORMAT_VERSION)
        FAIL("call stream version %lu; this replayer reads version %u",
             (unsigned long)rd32(s + 8), FORMAT_VERSION);
    width = rd32(s + 12);
    height = rd32(s + 16);
    flags = rd32(s + 20);
    if (width == 0 || height == 0 || width > 16384 || height > 16384)
        FAIL("target size %lux%lu is out of range", (unsigned long)width, (unsigned long)height);
    textures = (IDirect3DTexture9 **)calloc(MAX_TEXTURES, sizeof *textures);
    if (!textures)
        FAIL("out of memory");

    memset(&pp, 0, sizeof pp);
    pp.BackBufferWidth = width;
    pp.BackBufferHeight = height;
    pp.BackBufferFormat = D3DFMT_UNKNOWN;
    pp.BackBufferCount = 1;
    pp.SwapEffect = D3DSWAPEFFECT_DISCARD;
    pp.hDeviceWindow = r->window;
    pp.Windowed = TRUE;
    /* An automatic depth-stencil surface, so that D3DRS_ZENABLE defaults to D3DZB_TRUE. */
    pp.EnableAutoDepthStencil = TRUE;
    pp.AutoDepthStencilFormat = D3DFMT_D24S8;
    CHECK(IDirect3D9_CreateDevice(r->d3d, D3DADAPTER_DEFAULT, D3DDEVTYPE_HAL, r->window,
                                  (flags & FLAG_SOFTWARE_VP) ? D3DCREATE_SOFTWARE_VERTEXPROCESSING
                                                             : D3DCREATE_HARDWARE_VERTEXPROCESSING,
                                  &pp, &dev),
          "CreateDevice(HAL, %s vertex processing)",
          (flags & FLAG_SOFTWARE_VP) ? "software" : "hardware");
    CHECK(IDirect3DDevice9_CreateRenderTarget(dev, width, height, D3DFMT_A8R8G8B8,
                                              D3DMULTISAMPLE_NONE, 0, FALSE, &rt, NULL),
          "CreateRenderTarget(%lux%lu, A8R8G8B8)", (unsigned long)width, (unsigned long)height);
    CHECK(IDirect3DDevice9_SetRenderTarget(dev, 0, rt), "SetRenderTarget(0)");
    CHECK(IDirect3DDevice9_BeginScene(dev), "BeginScene");
    in_scene = 1;

    at = 24;
    for (;;) {
        uint32_t op, n;
        const unsigned char *p;
        if (at + 8 > len)
            FAIL("call stream ends without an end record (byte %lu)", (unsigned long)at);
        op = rd32(s + at);
        n = rd32(s + at + 4);
        if (n > len - at - 8)
            FAIL("record at byte %lu runs past the end of the stream", (unsigned long)at);
        p = s + at + 8;
#define NEED(k) do { if (n != (k)) FAIL("record at byte %lu (opcode %lu) has %lu bytes, not %lu", \
    (unsigned long)at, (unsigned long)op, (unsigned long)n, (unsigned long)(k)); } while (0)
        switch (op) {
        case OP_END:
            NEED(0);
            if (at + 8 != len)
                FAIL("bytes after the end record (byte %lu)", (unsigned long)(at + 8));
            goto replayed;
        case OP_CLEAR: {
            D3DVIEWPORT9 vp, full = {0, 0, width, height, 0.0f, 1.0f};
            NEED(8);
            /* The stream's clear covers the whole target, whatever the viewport. */
            CHECK(IDirect3DDevice9_GetViewport(dev, &vp), "GetViewport");
            CHECK(IDirect3DDevice9_SetViewport(dev, &full), "SetViewport(whole target)");
            CHECK(IDirect3DDevice9_Clear(dev, 0, NULL, D3DCLEAR_TARGET | D3DCLEAR_ZBUFFER,
                                         rd32(p), rdf(p + 4), 0),
                  "Clear(0x%08lX, %g)", (unsigned long)rd32(p), rdf(p + 4));
            CHECK(IDirect3DDevice9_SetViewport(dev, &vp), "SetViewport(restore)");
            break;
        }
        case OP_RENDER_STATE:
            NEED(8);
            CHECK(IDirect3DDevice9_SetRenderState(dev, (D3DRENDERSTATETYPE)rd32(p), rd32(p + 4)),
                  "SetRenderState(%lu, 0x%08lX)", (unsigned long)rd32(p),
                  (unsigned long)rd32(p + 4));
            break;
        case OP_TEXTURE_STAGE_STATE:
            NEED(12);
            CHECK(IDirect3DDevice9_SetTextureStageState(dev, rd32(p),
                                                        (D3DTEXTURESTAGESTATETYPE)rd32(p + 4),
                                                        rd32(p + 8)),
                  "SetTextureStageState(%lu, %lu, 0x%08lX)", (unsigned long)rd32(p),
                  (unsigned long)rd32(p + 4), (unsigned long)rd32(p + 8));
            break;
        case OP_SAMPLER_STATE:
            NEED(12);
            CHECK(IDirect3DDevice9_SetSamplerState(dev, rd32(p), (D3DSAMPLERSTATETYPE)rd32(p + 4),
                                                   rd32(p + 8)),
                  "SetSamplerState(%lu, %lu, 0x%08lX)", (unsigned long)rd32(p),
                  (unsigned long)rd32(p + 4), (unsigned long)rd32(p + 8));
            break;
        case OP_CREATE_TEXTURE: {
            uint32_t id, levels, l, w0, h0;
            size_t k = 8;
            if (n < 16)
                FAIL("CreateTexture record at byte %lu is too short", (unsigned long)at);
            id = rd32(p);
            levels = rd32(p + 4);
            w0 = rd32(p + 8);
            h0 = rd32(p + 12);
            if (id >= MAX_TEXTURES || textures[id])
                FAIL("CreateTexture record at byte %lu: id %lu is out of range or reused",
                     (unsigned long)at, (unsigned long)id);
            CHECK(IDirect3DDevice9_CreateTexture(dev, w0, h0, levels, 0, D3DFMT_A8R8G8B8,
                                                 D3DPOOL_MANAGED, &textures[id], NULL),
                  "CreateTexture(%lux%lu, %lu levels, A8R8G8B8, MANAGED)", (unsigned long)w0,
                  (unsigned long)h0, (unsigned long)levels);
            for (l = 0; l < levels; l++) {
                D3DSURFACE_DESC desc;
                uint32_t w, h;
                if (k + 8 > n)
                    FAIL("CreateTexture record at byte %lu is too short", (unsigned long)at);
                w = rd32(p + k);
                h = rd32(p + k + 4);
                k += 8;
                if ((uint64_t)w * h * 4 > n - k)
                    FAIL("CreateTexture record at byte %lu is too short", (unsigned long)at);
                CHECK(IDirect3DTexture9_GetLevelDesc(textures[id], l, &desc),
                      "GetLevelDesc(level %lu)", (unsigned long)l);
                if (desc.Width != w || desc.Height != h)
                    FAIL("CreateTexture: level %lu is %lux%lu on the device, %lux%lu in the "
                         "stream", (unsigned long)l, (unsigned long)desc.Width,
                         (unsigned long)desc.Height, (unsigned long)w, (unsigned long)h);
                CHECK(IDirect3DTexture9_LockRect(textures[id], l, &lr, NULL, 0),
                      "LockRect(texture %lu, level %lu)", (unsigned long)id, (unsigned long)l);
                for (y = 0; y < h; y++)
                    for (x = 0; x < w; x++)
                        ((DWORD *)((BYTE *)lr.pBits + (size_t)y * lr.Pitch))[x] =
                            rd32(p + k + ((size_t)y * w + x) * 4);
                CHECK(IDirect3DTexture9_UnlockRect(textures[id], l), "UnlockRect(level %lu)",
                      (unsigned long)l);
                k += (size_t)w * h * 4;
            }
            NEED(k);
            break;
        }
        case OP_SET_TEXTURE: {
            uint32_t id;
            NEED(8);
            id = rd32(p + 4);
            if (id != NO_TEXTURE && (id >= MAX_TEXTURES || !textures[id]))
                FAIL("SetTexture record at byte %lu names texture %lu, never created",
                     (unsigned long)at, (unsigned long)id);
            CHECK(IDirect3DDevice9_SetTexture(dev, rd32(p),
                                              id == NO_TEXTURE ? NULL
                                                               : (IDirect3DBaseTexture9 *)textures[id]),
                  "SetTexture(%lu, texture %ld)", (unsigned long)rd32(p),
                  id == NO_TEXTURE ? -1L : (long)id);
            break;
        }
        case OP_TRANSFORM: {
            D3DMATRIX m;
            int i;
            NEED(68);
            for (i = 0; i < 16; i++)
                m.m[i / 4][i % 4] = rdf(p + 4 + 4 * i);
            CHECK(IDirect3DDevice9_SetTransform(dev, (D3DTRANSFORMSTATETYPE)rd32(p), &m),
                  "SetTransform(%lu)", (unsigned long)rd32(p));
            break;
        }
        case OP_VIEWPORT: {
            D3DVIEWPORT9 vp;
            NEED(24);
            vp.X = rd32(p);
            vp.Y = rd32(p + 4);
            vp.Width = rd32(p + 8);
            vp.Height = rd32(p + 12);
            vp.MinZ = rdf(p + 16);
            vp.MaxZ = rdf(p + 20);
            CHECK(IDirect3DDevice9_SetViewport(dev, &vp), "SetViewport(%lu, %lu, %lu, %lu, %g, %g)",
                  (unsigned long)vp.X, (unsigned long)vp.Y, (unsigned long)vp.Width,
                  (unsigned long)vp.Height, vp.MinZ, vp.MaxZ);
            break;
        }
        case OP_CLIP_PLANE: {
            float plane[4];
            int i;
            NEED(20);
            for (i = 0; i < 4; i++)
                plane[i] = rdf(p + 4 + 4 * i);
            CHECK(IDirect3DDevice9_SetClipPlane(dev, rd32(p), plane), "SetClipPlane(%lu)",
                  (unsigned long)rd32(p));
            break;
        }
        case OP_DRAW_POINTS: {
            uint32_t fvf, stride, count, done = 0;
            if (n < 12)
                FAIL("DrawPoints record at byte %lu is too short", (unsigned long)at);
            fvf = rd32(p);
            stride = rd32(p + 4);
            count = rd32(p + 8);
            NEED(12 + (uint64_t)count * stride);
            CHECK(IDirect3DDevice9_SetFVF(dev, fvf), "SetFVF(0x%lX)", (unsigned long)fvf);
            /* A point list may be split anywhere: points are drawn in order either way. */
            while (done < count) {
                uint32_t k = count - done;
                if (r->caps.MaxPrimitiveCount && k > r->caps.MaxPrimitiveCount)
                    k = r->caps.MaxPrimitiveCount;
                CHECK(IDirect3DDevice9_DrawPrimitiveUP(dev, D3DPT_POINTLIST, k,
                                                       p + 12 + (size_t)done * stride, stride),
                      "DrawPrimitiveUP(POINTLIST, %lu points, stride %lu)", (unsigned long)k,
                      (unsigned long)stride);
                done += k;
            }
            break;
        }
        case OP_MATERIAL: {
            D3DMATERIAL9 m;
            NEED(68);
            memcpy(&m, p, 68);
            CHECK(IDirect3DDevice9_SetMaterial(dev, &m), "SetMaterial");
            break;
        }
        case OP_LIGHT: {
            D3DLIGHT9 light;
            NEED(4 + sizeof light);
            memcpy(&light, p + 4, sizeof light);
            CHECK(IDirect3DDevice9_SetLight(dev, rd32(p), &light), "SetLight(%lu)",
                  (unsigned long)rd32(p));
            break;
        }
        case OP_LIGHT_ENABLE:
            NEED(8);
            CHECK(IDirect3DDevice9_LightEnable(dev, rd32(p), rd32(p + 4) != 0),
                  "LightEnable(%lu, %lu)", (unsigned long)rd32(p), (unsigned long)rd32(p + 4));
            break;
        default:
            FAIL("unknown opcode %lu at byte %lu", (unsigned long)op, (unsigned long)at);
        }
#undef NEED
        at += 8 + (size_t)n;
    }

replayed:
    in_scene = 0;
    CHECK(IDirect3DDevice9_EndScene(dev), "EndScene");
    CHECK(IDirect3DDevice9_CreateOffscreenPlainSurface(dev, width, height, D3DFMT_A8R8G8B8,
                                                       D3DPOOL_SYSTEMMEM, &sys, NULL),
          "CreateOffscreenPlainSurface(SYSTEMMEM)");
    CHECK(IDirect3DDevice9_GetRenderTargetData(dev, rt, sys), "GetRenderTargetData");
    CHECK(IDirect3DSurface9_LockRect(sys, &lr, NULL, D3DLOCK_READONLY), "LockRect(target copy)");
    rgba = (unsigned char *)malloc((size_t)width * height * 4);
    if (rgba) {
        for (y = 0; y < height; y++) {
            const DWORD *row = (const DWORD *)((const BYTE *)lr.pBits + (size_t)y * lr.Pitch);
            for (x = 0; x < width; x++) {
                DWORD c = row[x];
                unsigned char *o = rgba + ((size_t)y * width + x) * 4;
                o[0] = (unsigned char)(c >> 16);
                o[1] = (unsigned char)(c >> 8);
                o[2] = (unsigned char)c;
                o[3] = (unsigned char)(c >> 24);
            }
        }
    }
    CHECK(IDirect3DSurface9_UnlockRect(sys), "UnlockRect(target copy)");
    if (!rgba)
        FAIL("out of memory");
    *out_w = width;
    *out_h = height;
    *out_rgba = rgba;
    rgba = NULL;
    ok = 1;

done:
    if (in_scene)
        IDirect3DDevice9_EndScene(dev);
    free(rgba);
    if (textures) {
        uint32_t i;
        for (i = 0; i < MAX_TEXTURES; i++)
            if (textures[i])
                IDirect3DTexture9_Release(textures[i]);
        free(textures);
    }
    if (sys)
        IDirect3DSurface9_Release(sys);
    if (rt)
        IDirect3DSurface9_Release(rt);
    if (dev)
        IDirect3DDevice9_Release(dev);
    return ok;
}

/* ---- the device's identity and caps ------------------------------------------------------- */

static void clean(char *s)
{
    for (; *s; s++)
        if (*s == '\n' || *s == '\r' || *s == '\t')
            *s = ' ';
}

static int write_device(struct replay *r, const char *path)
{
    D3DADAPTER_IDENTIFIER9 id;
    const char *(CDECL *wine_version)(void) = NULL;
    HMODULE ntdll = GetModuleHandleA("ntdll.dll");
    FILE *f = fopen(path, "w");
    if (!f)
        return 0;
    if (FAILED(IDirect3D9_GetAdapterIdentifier(r->d3d, D3DADAPTER_DEFAULT, 0, &id)))
        memset(&id, 0, sizeof id);
    clean(id.Description);
    clean(id.Driver);
    if (ntdll)
        wine_version = (const char *(CDECL *)(void))(void (*)(void))GetProcAddress(
            ntdll, "wine_get_version");
    fprintf(f, "format=1\n");
    fprintf(f, "description=%s\n", id.Description);
    fprintf(f, "driver=%s\n", id.Driver);
    fprintf(f, "driver_version=%lu.%lu.%lu.%lu\n",
            (unsigned long)HIWORD(id.DriverVersion.HighPart),
            (unsigned long)LOWORD(id.DriverVersion.HighPart),
            (unsigned long)HIWORD(id.DriverVersion.LowPart),
            (unsigned long)LOWORD(id.DriverVersion.LowPart));
    fprintf(f, "vendor_id=0x%04lX\ndevice_id=0x%04lX\n", (unsigned long)id.VendorId,
            (unsigned long)id.DeviceId);
    fprintf(f, "wine_version=%s\n", wine_version ? wine_version() : "");
    fprintf(f, "max_point_size=%.9g\n", r->caps.MaxPointSize);
    fprintf(f, "fvfcaps_psize=%d\n", (r->caps.FVFCaps & D3DFVFCAPS_PSIZE) ? 1 : 0);
    fprintf(f, "clip_plane_scaled_points=%d\n",
            (r->caps.PrimitiveMiscCaps & D3DPMISCCAPS_CLIPPLANESCALEDPOINTS) ? 1 : 0);
    fprintf(f, "clip_tl_verts=%d\n",
            (r->caps.PrimitiveMiscCaps & D3DPMISCCAPS_CLIPTLVERTS) ? 1 : 0);
    fprintf(f, "w_fog=%d\n", (r->caps.RasterCaps & D3DPRASTERCAPS_WFOG) ? 1 : 0);
    fprintf(f, "hw_transform_and_light=%d\n",
            (r->caps.DevCaps & D3DDEVCAPS_HWTRANSFORMANDLIGHT) ? 1 : 0);
    fprintf(f, "max_primitive_count=%lu\n", (unsigned long)r->caps.MaxPrimitiveCount);
    fprintf(f, "max_user_clip_planes=%lu\n", (unsigned long)r->caps.MaxUserClipPlanes);
    fprintf(f, "max_active_lights=%lu\n", (unsigned long)r->caps.MaxActiveLights);
    fprintf(f, "max_texture_size=%lux%lu\n", (unsigned long)r->caps.MaxTextureWidth,
            (unsigned long)r->caps.MaxTextureHeight);
    fprintf(f, "max_simultaneous_textures=%lu\n", (unsigned long)r->caps.MaxSimultaneousTextures);
    return fclose(f) == 0;
}

/* ---- main ---------------------------------------------------------------------------------- */

static unsigned char *read_file(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf = NULL;
    long n;
    if (!f)
        return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0) {
        buf = (unsigned char *)malloc((size_t)n + 1);
        if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
            free(buf);
            buf = NULL;
        }
        *len = (size_t)n;
    }
    fclose(f);
    return buf;
}

/* The case name of a stream path: its file name without the .calls extension. */
static void case_name(const char *path, char *out, size_t size)
{
    const char *base = path, *p;
    size_t n;
    for (p = path; *p; p++)
        if (*p == '/' || *p == '\\')
            base = p + 1;
    n = strlen(base);
    if (n > 6 && strcmp(base + n - 6, ".calls") == 0)
        n -= 6;
    if (n >= size)
        n = size - 1;
    memcpy(out, base, n);
    out[n] = 0;
}

static void run_one(struct replay *r, const char *out_dir, const char *path, FILE *results)
{
    char name[256], png[1024];
    size_t len = 0;
    unsigned char *s = read_file(path, &len), *rgba = NULL;
    uint32_t w = 0, h = 0;
    case_name(path, name, sizeof name);
    if (!s) {
        fprintf(results, "%s\terror\tcannot read %s\n", name, path);
    } else if (!replay(r, s, len, &w, &h, &rgba)) {
        clean(r->message);
        fprintf(results, "%s\terror\t%s\n", name, r->message);
    } else {
        snprintf(png, sizeof png, "%s/%s.png", out_dir, name);
        if (write_png(png, w, h, rgba))
            fprintf(results, "%s\tok\n", name);
        else
            fprintf(results, "%s\terror\tcannot write %s\n", name, png);
    }
    fflush(results);
    free(rgba);
    free(s);
}

int main(int argc, char **argv)
{
    struct replay r;
    WNDCLASSA wc;
    char path[1024];
    FILE *results;
    int i;

    if (argc < 3) {
        fprintf(stderr, "usage: replayer OUTDIR CALLS... (or @LIST)\n");
        return 2;
    }
    crc_init();
    memset(&r, 0, sizeof r);
    memset(&wc, 0, sizeof wc);
    wc.lpfnWndProc = DefWindowProcA;
    wc.hInstance = GetModuleHandleA(NULL);
    wc.lpszClassName = "pointillist_replayer";
    RegisterClassA(&wc);
    /* Never shown: the device renders into its own render target. */
    r.window = CreateWindowA("pointillist_replayer", "pointillist replayer", WS_OVERLAPPEDWINDOW,
                             0, 0, 64, 64, NULL, NULL, wc.hInstance, NULL);
    if (!r.window) {
        fprintf(stderr, "replayer: cannot create a window\n");
        return 2;
    }
    r.d3d = Direct3DCreate9(D3D_SDK_VERSION);
    if (!r.d3d) {
        fprintf(stderr, "replayer: Direct3DCreate9 failed\n");
        return 2;
    }
    if (FAILED(IDirect3D9_GetDeviceCaps(r.d3d, D3DADAPTER_DEFAULT, D3DDEVTYPE_HAL, &r.caps))) {
        fprintf(stderr, "replayer: GetDeviceCaps(HAL) failed: no hardware device\n");
        return 2;
    }
    CreateDirectoryA(argv[1], NULL);
    snprintf(path, sizeof path, "%s/device.txt", argv[1]);
    if (!write_device(&r, path)) {
        fprintf(stderr, "replayer: cannot write %s\n", path);
        return 2;
    }
    snprintf(path, sizeof path, "%s/results.txt", argv[1]);
    results = fopen(path, "a");
    if (!results) {
        fprintf(stderr, "replayer: cannot write %s\n", path);
        return 2;
    }
    for (i = 2; i < argc; i++) {
        if (argv[i][0] == '@') {
            FILE *list = fopen(argv[i] + 1, "r");
            char line[1024];
            if (!list) {
                fprintf(stderr, "replayer: cannot read the list %s\n", argv[i] + 1);
                return 2;
            }
            while (fgets(line, sizeof line, list)) {
                line[strcspn(line, "\r\n")] = 0;
                if (line[0])
                    run_one(&r, argv[1], line, results);
            }
            fclose(list);
        } else {
            run_one(&r, argv[1], argv[i], results);
        }
    }
    fclose(results);
    IDirect3D9_Release(r.d3d);
    DestroyWindow(r.window);
    return 0;
}
