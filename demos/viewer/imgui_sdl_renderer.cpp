#include "imgui_sdl_renderer.h"

#include <SDL.h>
#include <imgui.h>

namespace rg::viewer {

namespace {
SDL_Renderer* gRenderer = nullptr;
SDL_Texture* gFont = nullptr;
}  // namespace

bool imguiSdlRendererInit(SDL_Renderer* renderer) {
    gRenderer = renderer;
    ImGuiIO& io = ImGui::GetIO();
    io.BackendRendererName = "retroglass_sdl_renderer";
    io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    // RGBA bytes in memory: SDL's RGBA32 alias picks the packed format for this endianness.
    gFont = SDL_CreateTexture(renderer, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STATIC, w, h);
    if (!gFont) return false;
    SDL_UpdateTexture(gFont, nullptr, pixels, w * 4);
    SDL_SetTextureBlendMode(gFont, SDL_BLENDMODE_BLEND);
    io.Fonts->SetTexID(reinterpret_cast<ImTextureID>(gFont));
    return true;
}

void imguiSdlRendererShutdown() {
    if (gFont) SDL_DestroyTexture(gFont);
    gFont = nullptr;
    gRenderer = nullptr;
    ImGui::GetIO().Fonts->SetTexID(nullptr);
}

void imguiSdlRendererDraw(ImDrawData* dd) {
    if (!gRenderer || !dd) return;
    SDL_Rect oldClip;
    SDL_bool hadClip = SDL_RenderIsClipEnabled(gRenderer);
    SDL_RenderGetClipRect(gRenderer, &oldClip);
    const ImVec2 origin = dd->DisplayPos;
    for (int n = 0; n < dd->CmdListsCount; ++n) {
        const ImDrawList* list = dd->CmdLists[n];
        const ImDrawVert* vtx = list->VtxBuffer.Data;
        const ImDrawIdx* idx = list->IdxBuffer.Data;
        for (const ImDrawCmd& cmd : list->CmdBuffer) {
            if (cmd.UserCallback) {
                if (cmd.UserCallback != ImDrawCallback_ResetRenderState) cmd.UserCallback(list, &cmd);
                continue;
            }
            SDL_Rect clip{int(cmd.ClipRect.x - origin.x), int(cmd.ClipRect.y - origin.y),
                          int(cmd.ClipRect.z - cmd.ClipRect.x), int(cmd.ClipRect.w - cmd.ClipRect.y)};
            if (clip.w <= 0 || clip.h <= 0) continue;
            SDL_RenderSetClipRect(gRenderer, &clip);
            const ImDrawVert* v = vtx + cmd.VtxOffset;
            // ImDrawVert: pos (2 floats), uv (2 floats), col (RGBA bytes = SDL_Color).
            SDL_RenderGeometryRaw(
                gRenderer, static_cast<SDL_Texture*>(cmd.GetTexID()),
                reinterpret_cast<const float*>(reinterpret_cast<const char*>(v) + offsetof(ImDrawVert, pos)),
                sizeof(ImDrawVert),
                reinterpret_cast<const SDL_Color*>(reinterpret_cast<const char*>(v) + offsetof(ImDrawVert, col)),
                sizeof(ImDrawVert),
                reinterpret_cast<const float*>(reinterpret_cast<const char*>(v) + offsetof(ImDrawVert, uv)),
                sizeof(ImDrawVert), int(list->VtxBuffer.Size - int(cmd.VtxOffset)),
                idx + cmd.IdxOffset, int(cmd.ElemCount), int(sizeof(ImDrawIdx)));
        }
    }
    SDL_RenderSetClipRect(gRenderer, hadClip ? &oldClip : nullptr);
}

}  // namespace rg::viewer
