"""The gallery page docs/gallery.md (written by tools/gallery) shows every image of docs/gallery/
and nothing else, each image is a preset's summary at most 150 KB, under the title of its preset
(its first comment up to a colon)."""
import re
import sys
import unittest

import matplotlib.image

import small_run

PAGE = small_run.SOURCE_DIR / "docs" / "gallery.md"
GALLERY = small_run.SOURCE_DIR / "docs" / "gallery"
PRESETS = small_run.SOURCE_DIR / "ensembles" / "presets"


class Gallery(unittest.TestCase):
    def test_page_shows_every_image_under_its_preset(self):
        text = PAGE.read_text()
        begin, end = "<!-- gallery: written by tools/gallery -->", "<!-- end of gallery -->"
        self.assertIn(begin, text)
        section = text[text.index(begin):text.index(end)]
        # Images relative to the page (docs/), as MyST and a forge's viewer both resolve them.
        shown = re.findall(r"^## (.*)\n\n`ensembles/presets/([^`]+)\.toml`.*\n\n"
                           r"!\[[^\]]*\]\(gallery/([^)]+)\.png\)", section, re.M)
        self.assertEqual(len(shown), section.count("!["), "every image under a heading")
        self.assertEqual(sorted(s[2] for s in shown), sorted(p.stem for p in GALLERY.glob("*.png")))
        self.assertGreaterEqual(len(shown), 1)
        for title, preset, image in shown:
            with self.subTest(image=image):
                self.assertEqual(preset, image)
                path = PRESETS / f"{preset}.toml"
                self.assertTrue(path.exists(), f"{path} is gone")
                lines = path.read_text().splitlines()
                start = next(i for i, line in enumerate(lines) if line.startswith("#"))
                comment = []
                for line in lines[start:]:
                    if not line.startswith("#"):
                        break
                    comment.append(line.lstrip("#").strip())
                comment = " ".join(comment)
                self.assertTrue(comment.startswith(title), f"{title!r} begins {path.name}'s comment")
                self.assertIn(comment[len(title):][:1], ("", ":"), "the title ends at a colon")

    def test_images_are_small_summaries(self):
        for image in GALLERY.glob("*.png"):
            with self.subTest(image=image.name):
                self.assertLessEqual(image.stat().st_size, 150 * 1024)
                pixels = matplotlib.image.imread(image)
                self.assertGreaterEqual(min(pixels.shape[:2]), 300)
                self.assertGreater((pixels[..., :3] < 0.9).any(axis=2).mean(), 0.05)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
