"""par2d from Python, notebook style: build a scene, render it to NumPy, move a light with a Renderer, save a PNG.

Run: PYTHONPATH=build/python python3 examples/python_quickstart.py [OUT.png]
Each `# %%` block is a cell (Jupyter, VS Code and Spyder run them one by one).
"""
# %% A scene is a dict shaped like the JSON file (or par2d.load_scene("examples/paper.json")).
import sys

import numpy as np

import par2d

scene = {
    "width": 320, "height": 200,
    "lights": [
        {"circle": {"center": [60, 60], "radius": 8}, "color": [1.0, 0.8, 0.5], "intensity": 3},
        {"segment": [[200, 180], [300, 170]], "color": [0.3, 0.5, 1.0], "intensity": 2},
    ],
    "occluders": [
        {"polygon": [[140, 70], [180, 70], [180, 110], [140, 110]]},
        {"circle": {"center": [240, 80], "radius": 18}},
    ],
}

# %% Render: a float32 array of linear irradiance, shape (height, width, 3), row 0 at the top.
image = par2d.render(scene)
print(f"{image.shape} {image.dtype}, max {image.max():.3f}, mean {image.mean():.4f}, ISA {par2d.default_isa()}")

# %% The shadow of the square: a pixel right behind it (as seen from the warm light) gets no warm light.
behind = image[100, 220]  # row 100, column 220: beyond the square from (60, 60)
blue_only = par2d.render(dict(scene, lights=scene["lights"][1:]))[100, 220]
print("behind the square:", behind, "- the blue light alone gives", blue_only)

# %% Move the warm light, frame after frame: a Renderer keeps the world prepared and changes it
# through handles; moving a light never rebuilds the occluder index.
renderer = par2d.Renderer(scene)
warm = renderer.lights[0]
for x in (80, 120, 160):
    scene["lights"][0]["circle"]["center"] = [x, 20]
    renderer.update_light(warm, scene["lights"][0])
    image2 = renderer.render()
print("changed pixels:", int(np.count_nonzero(np.any(image2 != image, axis=2))), "of", 320 * 200)
# The same image as a one-shot render of the moved scene, bit for bit.
assert np.array_equal(image2, par2d.render(scene))
print("renderer:", renderer.stats)

# %% Errors are par2d.Error with the loader's one-line message and a code.
try:
    par2d.Scene.from_dict({"width": 320, "height": 200, "lights": [{"circle": {"center": [0, 0], "radius": -1}}]})
except par2d.Error as e:
    print(f"refused ({e.code}): {e}")

# %% Save: the scene as JSON (par2d.Scene.save) and the image as an sRGB PNG, as `par2d render -o` writes it.
if len(sys.argv) > 1:
    par2d.write_png(sys.argv[1], image2, exposure=1.5)
    print("wrote", sys.argv[1])
