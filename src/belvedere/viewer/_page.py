"""JavaScript the viewer runs in every page of its server, and what it runs there."""

from __future__ import annotations

import json
from typing import Any, Final

__all__ = ["PAGE_TEXELS", "run_in_page", "sharpen_texels"]


def run_in_page(gui: Any, source: str) -> None:
    """Run ``source`` in every page of ``gui``'s server, those open and those to come."""
    from viser import _messages  # heavy: only the viewer imports viser

    # viser's add_plotly sends its JavaScript this way; the message is kept for pages that
    # connect later (viser never culls it)
    gui._websock_interface.queue_message(_messages.RunJavascriptMessage(source=source))


PAGE_TEXELS: Final = """
if (!window.__belvedereTexels) {
  // Scene nodes whose textures are drawn texel by texel. viser's image node samples through
  // mipmaps with linear filtering: a software renderer pays for that at every pixel, and
  // the map's cells blur into each other. rviz's map is not filtered either.
  const names = window.__belvedereTexels = new Set();
  const NEAREST = 1003;
  const sharpen = () => {
    const nodes = window.__viserMutable && window.__viserMutable.nodeRefFromName;
    if (nodes) {
      for (const name of names) {
        const node = nodes[name];
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
    }
    requestAnimationFrame(sharpen);
  };
  requestAnimationFrame(sharpen);
}
"""


def sharpen_texels(gui: Any, name: str) -> None:
    """Have every page draw the texture of scene node ``name`` (a viser image) with no
    filtering, each texel a sharp square, as rviz draws a map."""
    run_in_page(gui, PAGE_TEXELS + f"window.__belvedereTexels.add({json.dumps(name)});\n")
