#!/usr/bin/env python3
"""clothvk-render --video FILE: the images piped into ffmpeg, encoded as a video.

    python3 tests/tools/test_video.py PATH/TO/clothvk-render

Always: without ffmpeg on PATH, --video is refused before any work with one line saying how to
get it (exit status 2, nothing written), and so is --video without a name.

With ffmpeg installed (else these cases are skipped, with the reason printed): a name without
an extension or of a folder is refused the same way; a 24 x 24 cloth
rendered at 160 x 90 for 41 frames, every 20, with -o and --video must give exactly 3 PNGs and
a video of 3 frames of 160 x 90 at 1 / (dt · substeps · 20) frames per second (ffprobe's count).
Each video frame, decoded by ffmpeg, must match its PNG up to the encoder's loss (mean absolute
difference per channel under 3 of 255, where it measures about 1.5; red and blue swapped gives
about 8) and be nearer its own PNG than the other two (the cloth falls between them). An odd size is padded to even (yuv420p), --video
without -o writes the video alone, .webm (any case), .gif, .avi and .mov give videos of their
frames, and an extension outside that list is refused before any work, exit status 2, nothing
written.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import tooltest

[RENDER] = tooltest.tool_paths("clothvk-render")
ROOT = tooltest.ROOT

HANGING = os.path.join(ROOT, "assets", "scenes", "hanging.json")
TINY = [HANGING, "--set", "cloths.0.grid=[24,24]", "--set", "cloths.0.pins=[[0,0],[23,0]]"]
FFMPEG = shutil.which("ffmpeg")
FFPROBE = shutil.which("ffprobe")


def error(message):
    return tooltest.tool_line("clothvk-render", message)


def run(argv, cwd, env=None):
    return tooltest.run_tool(RENDER, argv, cwd, env, timeout=300)


def frame_rate():
    with open(HANGING) as f:
        scene = json.load(f)
    return 1.0 / (scene["dt"] * scene["substeps"] * 20)


def probe(path):
    p = subprocess.run([FFPROBE, "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                        "stream=nb_read_frames,width,height,avg_frame_rate", "-of", "json", path],
                       capture_output=True, text=True, timeout=120)
    stream = json.loads(p.stdout)["streams"][0]
    num, den = stream["avg_frame_rate"].split("/")
    rate = float(num) / float(den) if float(den) else 0.0  # a GIF has no average rate: 0/0
    return int(stream["nb_read_frames"]), stream["width"], stream["height"], rate


def decode(path, index=None):
    """RGB bytes of a PNG, or of frame `index` of a video, decoded by ffmpeg."""
    select = ["-vf", f"select=eq(n\\,{index})", "-frames:v", "1"] if index is not None else []
    p = subprocess.run([FFMPEG, "-v", "error", "-i", path] + select + ["-f", "rawvideo", "-pix_fmt", "rgb24", "-"],
                       capture_output=True, timeout=120)
    return p.stdout


def mean_difference(a, b):
    if len(a) != len(b) or not a:
        return float("inf")
    return sum(abs(x - y) for x, y in zip(a, b)) / len(a)


# ---- cases ----


def without_ffmpeg():
    """PATH without ffmpeg: refused before any work."""
    with tempfile.TemporaryDirectory(prefix="clothvk-video-") as workdir:
        empty = os.path.join(workdir, "bin")
        os.mkdir(empty)
        env = dict(os.environ, PATH=empty)
        return expect_refusal(TINY + ["-o", "frames", "--video", "clip.mp4"], workdir, env,
                              error("--video needs ffmpeg: apt-get install ffmpeg"))


def expect_refusal(argv, workdir, env, expected):
    before = tooltest.listing(workdir)
    p = run(argv, workdir, env)
    return tooltest.refusal_problems(p, expected, before, tooltest.listing(workdir))


def bad_name(argv, files, expected):
    def check():
        with tempfile.TemporaryDirectory(prefix="clothvk-video-") as workdir:
            for name in files:
                os.makedirs(os.path.join(workdir, name))
            return expect_refusal(TINY + ["--frames", "1"] + argv, workdir, None, expected)
    return check


def with_pngs():
    with tempfile.TemporaryDirectory(prefix="clothvk-video-") as workdir:
        p = run(TINY + ["--size", "160x90", "--frames", "41", "--every", "20", "-o", "frames", "--video",
                        "out/clip.mp4", "--quiet"], workdir)
        if p.returncode != 0 or p.stderr:
            return [f"exit status {p.returncode}, stderr: {p.stderr.strip()}"]
        expected = ["frames", "frames/frame_0000.png", "frames/frame_0001.png", "frames/frame_0002.png",
                    "out", "out/clip.mp4"]
        if tooltest.listing(workdir) != expected:
            return [f"found {tooltest.listing(workdir)}, expected {expected}"]
        problems = []
        clip = os.path.join(workdir, "out", "clip.mp4")
        frames, width, height, rate = probe(clip)
        if (frames, width, height) != (3, 160, 90) or abs(rate - frame_rate()) > 1e-3 * frame_rate():
            problems.append(f"the video has {frames} frames of {width} x {height} at {rate:.4g} fps, expected "
                            f"3 of 160 x 90 at {frame_rate():.4g}")
        pngs = [decode(os.path.join(workdir, "frames", f"frame_{i:04d}.png")) for i in range(3)]
        for index in range(3):
            gaps = [mean_difference(decode(clip, index), png) for png in pngs]
            if gaps[index] > 3 or min(gaps) != gaps[index]:
                problems.append(f"video frame {index} differs from frame_0000.png to frame_0002.png by "
                                f"{', '.join(f'{g:.3g}' for g in gaps)} of 255 on average: expected under 3 "
                                f"and least for frame_{index:04d}.png")
        return problems


def video_only_odd_size():
    with tempfile.TemporaryDirectory(prefix="clothvk-video-") as workdir:
        # --frames 1: the start and the state after one frame.
        p = run(TINY + ["--size", "161x91", "--frames", "1", "--video", "clip.mkv", "--quiet"], workdir)
        if p.returncode != 0 or p.stderr:
            return [f"exit status {p.returncode}, stderr: {p.stderr.strip()}"]
        if tooltest.listing(workdir) != ["clip.mkv"]:
            return [f"found {tooltest.listing(workdir)}, expected clip.mkv alone"]
        frames, width, height, _ = probe(os.path.join(workdir, "clip.mkv"))
        if (frames, width, height) != (2, 162, 92):
            return [f"the video has {frames} frames of {width} x {height}, expected 2 of 162 x 92"]
        return []


def other_containers():
    """The other containers of the list, the extension in any case: each a video of its frames."""
    problems = []
    for name in ("clip.WEBM", "clip.gif", "clip.avi", "clip.mov"):
        with tempfile.TemporaryDirectory(prefix="clothvk-video-") as workdir:
            p = run(TINY + ["--size", "32x32", "--frames", "1", "--video", name, "--quiet"], workdir)
            if p.returncode != 0 or p.stderr:
                problems.append(f"{name}: exit status {p.returncode}, stderr: {p.stderr.strip()}")
            elif tooltest.listing(workdir) != [name]:
                problems.append(f"{name}: found {tooltest.listing(workdir)}, expected {name} alone")
            elif probe(os.path.join(workdir, name))[:3] != (2, 32, 32):
                problems.append(f"{name}: (frames, width, height) is "
                                f"{probe(os.path.join(workdir, name))[:3]}, expected (2, 32, 32)")
    return problems


def main():
    cases = tooltest.Cases("video")
    checks = [("without ffmpeg", without_ffmpeg),
              ("--video without a name", bad_name(["--video"], [], error("--video: expected a file name such as clip.mp4"))),
]
    skipped = ""
    if FFMPEG and FFPROBE:
        # The name is checked once ffmpeg is known to be there.
        checks += [("--video name without an extension", bad_name(["--video", "clip"], [],
                    error("--video clip: expected a name whose extension names the format, such as clip.mp4"))),
                   ("--video name of a folder", bad_name(["--video", "taken.mp4"], ["taken.mp4"],
                    error("--video taken.mp4: is a folder; expected a file name such as clip.mp4"))),
                   # A container outside the list is refused before any work (ffmpeg would
                   # refuse it only once frames were drawn); nothing is made, not even its folder.
                   ("--video of an unknown format", bad_name(["-o", "frames", "--video", "out/clip.xyz"], [],
                    error("--video out/clip.xyz: unknown video format .xyz (expected .mp4, .mkv, .mov, "
                          ".webm, .avi or .gif)"))),
                   ("-o and --video", with_pngs), ("--video alone, odd size", video_only_odd_size),
                   ("--video .WEBM and .gif", other_containers)]
    else:
        skipped = " (skipped the encoding cases: ffmpeg or ffprobe is not on PATH; apt-get install ffmpeg)"
    for name, check in checks:
        cases.add(name, check())
    return cases.finish(skipped)


if __name__ == "__main__":
    sys.exit(main())
