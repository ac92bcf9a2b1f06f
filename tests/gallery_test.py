"""The README's gallery (written by tools/gallery) shows every image of docs/gallery/ and nothing
else, each image is a preset's summary at most 150 KB, under the title of its preset."""
import re
import sys
import unittest

import matplotlib.image

import small_run

README = small_run.SOURCE_DIR / "README.md"
GALLERY = small_run.SOURCE_DIR / "docs" / "gallery"
PRESETS = small_run.SOURCE_DIR / "ensembles" / "presets"


class Gallery(unittest.TestCase):
    def test_readme_shows_every_image_under_its_preset(self):
        text = README.read_text()
        begin, end = "<!-- gallery: written by tools/gallery -->", "<!-- end of gallery -->"
        self.assertIn(begin, text)
        section = text[text.index(begin):text.index(end)]
        shown = re.findall(r"^### (.*)\n\n`ensembles/presets/([^`]+)\.toml`.*\n\n"
                           r"!\[[^\]]*\]\(docs/gallery/([^)]+)\.png\)", section, re.M)
        self.assertEqual(len(shown), section.count("!["), "every image under a heading")
        self.assertEqual(sorted(s[2] for s in shown), sorted(p.stem for p in GALLERY.glob("*.png")))
        self.assertGreaterEqual(len(shown), 1)
        for title, preset, image in shown:
            with self.subTest(image=image):
                self.assertEqual(preset, image)
                path = PRESETS / f"{preset}.toml"
                self.assertTrue(path.exists(), f"{path} is gone")
                first_comment = next(line for line in path.read_text().splitlines()
                                     if line.startswith("#"))
                self.assertIn(title, first_comment)

    def test_images_are_small_summaries(self):
        for image in GALLERY.glob("*.png"):
            with self.subTest(image=image.name):
                self.assertLessEqual(image.stat().st_size, 150 * 1024)
                pixels = matplotlib.image.imread(image)
                self.assertGreaterEqual(min(pixels.shape[:2]), 300)
                self.assertGreater((pixels[..., :3] < 0.9).any(axis=2).mean(), 0.05)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
