"""JavaScript the viewer runs in every page of its server, and what it runs there."""

from __future__ import annotations

import json
from typing import Any, Final

__all__ = ["PAGE_DRAWING", "page_background", "run_in_page", "sharpen_texels"]


def run_in_page(gui: Any, source: str) -> None:
    """Run ``source`` in every page of ``gui``'s server, those open and those to come."""
    from viser import _messages  # heavy: only the viewer imports viser

    # viser's add_plotly sends its JavaScript this way; the message is kept for pages that
    # connect later (viser never culls it)
    gui._websock_interface.queue_message(_messages.RunJavascriptMessage(source=source))


PAGE_DRAWING: Final = """
if (!window.__belvedereDrawing) {
  // What a software renderer (WebGL without a GPU) pays for at every pixel and rviz does not
  // draw, changed in the page: viser has no setting for either.
  // - Textures of the scene nodes named in `texels` are drawn texel by texel: viser's image
  //   node samples through mipmaps with linear filtering, blurring a map's cells together.
  // - With a flat `background` colour, viser's background pass (a full-view quad drawing
  //   its background image) is hidden and the colour is the page's, behind the canvas
  //   (three.js clears it transparent): the same pixels, a pass fewer.
  const state = window.__belvedereDrawing = {texels: new Set(), background: null};
  const NEAREST = 1003;
  let quad = null, frames = 0;
  const draw = () => {
    const viewer = window.__viserMutable;
    if (viewer && viewer.nodeRefFromName) {
      for (const name of state.texels) {
        const node = viewer.nodeRefFromName[name];
        if (!node) continue;
        node.traverse((o) => {
          const t = o.material && o.material.map;  // loaded after the node is made
          if (t && t.minFilter !== NEAREST) {
            t.minFilter = NEAREST;
            t.magFilter = NEAREST;
            t.generateMipmaps = false;
            t.needsUpdate = true;
          }
        });
      }
      if (state.background !== null && viewer.scene && viewer.canvas) {
        if ((quad === null || quad.parent === null) && frames++ % 30 === 0) {
          quad = null;
          viewer.scene.traverse((o) => {
            if (o.material && o.material === viewer.backgroundMaterial) quad = o;
          });
        }
        if (quad !== null) {
          quad.visible = false;
          viewer.canvas.style.backgroundColor = state.background;
        }
      }
    }
    requestAnimationFrame(draw);
  };
  requestAnimationFrame(draw);
}
"""


def sharpen_texels(gui: Any, name: str) -> None:
    """Have every page draw the texture of scene node ``name`` (a viser image) with no
    filtering, each texel a sharp square, as rviz draws a map."""
    run_in_page(gui, PAGE_DRAWING + f"window.__belvedereDrawing.texels.add({json.dumps(name)});")


def page_background(gui: Any, rgb: tuple[int, int, int]) -> None:
    """Have every page show the flat background colour ``rgb`` behind the 3D view itself, not
    through viser's background pass (which the caller also sets: a page without the script
    shows the colour all the same)."""
    color = "rgb({}, {}, {})".format(*(int(c) for c in rgb))
    run_in_page(gui, PAGE_DRAWING + f"window.__belvedereDrawing.background = {json.dumps(color)};")
