# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#       format_version: '1.3'
#       jupytext_version: 1.19.7
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 08 · From a scan to a typeface
#
# **What you should see.** The thesis's word 'Ali' and its letter D are traced from bitmaps into smooth
# outlines, then the D is edited like a designer would: one knot moved, one corner turned smooth, the handle of
# another corner pulled, the whole letter slanted. At the end the glyphs become a small font (UFO, OpenType/CFF and TrueType files), and a line
# of text is set in it.
#
# The loop is the one of the thesis's conclusion (section 5.1): capture an object's outline as splines, "then
# apply all transformations on it, thus allowing a designer to play with the shape". Every edit acts on knots
# and handles (thesis section 3.3, "transform only the control points"), and every contour is rebuilt by the
# engine after each edit.

# %%
import base64
import io
import math
import tempfile

import numpy as np
from IPython.display import HTML, Image, display

import splinecraft as sc
from splinecraft import datasets

ali_trace = sc.trace(datasets.thesis_object("ali"))
d_trace = sc.trace(datasets.thesis_object("D"))
ali_trace, d_trace

# %% [markdown]
# ## 1 · The captured outline as an editable shape
#
# `sc.outline.as_outline` turns a trace into contours of *knots*. Between knots the curve is the engine's
# interpolant: GC² joints at smooth knots (thesis eqs 3.13-3.14, with a point tension per knot and an interval
# weight per piece), and corners where the trace found them, each with its two handles. The conversion is
# exact: the editable D is the traced D to rounding. Its source contour (the bitmap's crack outline) stays
# attached, so the deviation of every piece from the scan can be shown at any time.

# %%
d_outline = sc.outline.as_outline(d_trace)
print(d_outline)
print("largest change from the traced curves:",
      max(np.abs(a - b).max() for a, b in zip(d_outline.bezier(), d_trace.bezier())), "px")
print("max deviation from the bitmap:", round(d_outline.max_deviation(), 3), "px")

# %% [markdown]
# ## 2 · The editor
#
# Drag a knot; `C` toggles corner / smooth; a selected corner shows its two handles, drag one to reshape the
# curve next to the corner; double-click the curve to insert a knot, Delete removes one; click the curve to
# select a contour, or drag a box; the handles of the selection's box rotate, scale and shear it;
# Ctrl+Z undoes. Tick **deviation** to colour every piece by its distance from the scan (the status line gives
# the maximum). The same edits are methods of the editor, used below.

# %%
editor = sc.OutlineEditor(d_trace, width=560, height=460)
display(editor)

# %% [markdown]
# ## 3 · Four edits from code
#
# * move the knot of the outer contour that lies farthest right (the bowl's rightmost point) 10 px further
#   right;
# * turn the corner of the top serif (the top-left corner of the outer contour) into a smooth knot;
# * pull the outgoing handle of the bottom-left corner 8 px to the left: the Bézier control point next to the
#   corner goes exactly there, and only the curve between this corner and the next one changes;
# * slant the whole letter by 12°, an italic: a shear of the knots and handles, which shears the curve
#   exactly.

# %%
outer = editor.outline.contours[0]
right = int(np.argmax(outer.points[:, 0]))
editor.move_knot(0, right, outer.points[right] + [10.0, 0.0])

corner_knots = np.flatnonzero(editor.outline.contours[0].corners)
top_left = int(corner_knots[np.argmin(editor.outline.contours[0].points[corner_knots].sum(axis=1))])
editor.set_corner(0, top_left, False)

corner_knots = np.flatnonzero(editor.outline.contours[0].corners)
corner_points = editor.outline.contours[0].points[corner_knots]
bottom_left = int(corner_knots[np.argmax(corner_points[:, 1] - corner_points[:, 0])])  # y points down
handle_point = editor.outline.contours[0].bezier()[bottom_left, 1] + [-8.0, 0.0]
editor.move_handle(0, bottom_left, "out", handle_point)

before_slant = editor.outline
editor.selection = []          # nothing selected: the transform acts on the whole shape
editor.slant(12)
print(editor.status_message)


# %%
def drawing(outline, title, color):
    return sc.plot.figure(*[sc.plot.bezier_pieces(b, color) for b in outline.bezier()], title=title)


display(sc.plot.grid(drawing(d_outline, "traced", sc.plot.PALETTE[0]),
                     drawing(editor.outline, "edited", sc.plot.PALETTE[1])))

# %% [markdown]
# ## 4 · A small font
#
# `sc.font.build` writes a UFO source and two compiled fonts: OpenType with CFF outlines (the cubics
# themselves) and TrueType (quadratics from fontTools' `cu2qu`, within `ttf_max_error` = 0.25 font units).
# Contours are oriented for each format, so the counters of the D and of 'Ali' stay open. The glyphs: `d` the
# traced D, `D` the edited one, and `A` the whole word 'Ali'.

# %%
font_dir = tempfile.TemporaryDirectory(prefix="font_08_")      # removed at the end of the notebook
files = sc.font.build({"d": d_trace, "D": editor, "A": ali_trace}, family="Scan Sans", output_dir=font_dir.name)
files.paths, round(files.scale, 4)

# %%
from PIL import Image as PILImage, ImageDraw, ImageFont

face = ImageFont.truetype(str(files.ttf), 96)
text = "dD A dD"
sample = PILImage.new("L", (760, 150), 255)
ImageDraw.Draw(sample).text((16, 24), text, font=face, fill=0)
buffer = io.BytesIO()
sample.save(buffer, format="PNG")
display(Image(buffer.getvalue()))

otf = base64.b64encode(files.otf.read_bytes()).decode()
display(HTML(f'''<style>@font-face {{ font-family: "Scan Sans 08"; src: url(data:font/otf;base64,{otf}); }}</style>
<div style="font-family: 'Scan Sans 08'; font-size: 64px; line-height: 1.2">{text}</div>'''))

# %%
# Check: what this notebook claimed
from fontTools.ttLib import TTFont

# the editable outlines reproduce the traces exactly
for trace in (ali_trace, d_trace):
    outline = sc.outline.as_outline(trace)
    assert max(np.abs(a - b).max() for a, b in zip(outline.bezier(), trace.bezier())) < 1e-9
# one knot moved, one corner fewer, the handle's control point where it was put, the slant an exact shear
assert int(editor.outline.contours[0].corners.sum()) == int(d_outline.contours[0].corners.sum()) - 1
assert np.abs(before_slant.contours[0].bezier()[bottom_left, 1] - handle_point).max() < 1e-9
center = before_slant.selection_center()
shear = -math.tan(math.radians(12))
for old, new in zip(before_slant.bezier(), editor.outline.bezier()):
    expected = old.copy()
    expected[..., 0] += shear * (old[..., 1] - center[1])
    assert np.abs(new - expected).max() < 1e-9
# the font files exist and hold the three glyphs; the text sample has ink
for path in files.paths.values():
    assert path.exists()
ttf = TTFont(files.ttf)
assert {ord("d"), ord("D"), ord("A")} <= set(ttf.getBestCmap())
assert (np.asarray(sample) < 128).sum() > 2000
font_dir.cleanup()                                   # the font files were for this notebook only
print("all checks passed")
