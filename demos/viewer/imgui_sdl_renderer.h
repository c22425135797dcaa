// Dear ImGui draw lists through SDL_Renderer (SDL_RenderGeometryRaw, SDL ≥ 2.0.18), our
// own renderer backend: Debian's libimgui-dev ships the SDL2 platform backend but not the
// SDL renderer one. Works with the software renderer, so the viewer needs no GPU.
#pragma once

struct SDL_Renderer;
struct ImDrawData;

namespace rg::viewer {

bool imguiSdlRendererInit(SDL_Renderer* renderer);   // creates the font texture
void imguiSdlRendererShutdown();
void imguiSdlRendererDraw(ImDrawData* drawData);

}  // namespace rg::viewer
