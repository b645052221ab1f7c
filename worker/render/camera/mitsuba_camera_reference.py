"""Reference rays for the cameras (camera_test.cpp) from Mitsuba 3.

Run with a Python that has mitsuba installed (scalar_rgb variant):
    python worker/render/camera/mitsuba_camera_reference.py > worker/render/camera/mitsuba_camera_reference.inc
It prints the sensors' XML as C++ raw strings (kCameraXml) and table rows: the sensor's index,
the film sample in [0, 1]^2 (x right, y down) and the ray Mitsuba's sample_ray makes from it
(origin, unit direction). The orthographic sensors have a scale in their to_world (it sets the
view size; one non-uniform, one with a scale along the view axis, which moves the near plane)
and a near_clip (the rays start there); the perspective one checks that both share the frame.
"""
import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

SENSORS = [
    """<sensor type="orthographic">
  <float name="near_clip" value="0.5"/>
  <transform name="to_world"><scale x="2" y="3" z="1.5"/>
    <lookat origin="1, 2, 3" target="2, 1, 5" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="30"/>
    <rfilter type="box"/></film>
</sensor>""",
    """<sensor type="orthographic">
  <transform name="to_world"><scale x="300" y="300"/>
    <lookat origin="278, 273, -800" target="278, 273, -799" up="0, 1, 0"/></transform>
  <float name="near_clip" value="10"/><float name="far_clip" value="2800"/>
  <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="32"/>
    <rfilter type="box"/></film>
</sensor>""",
    """<sensor type="perspective">
  <float name="fov" value="50"/><string name="fov_axis" value="y"/>
  <transform name="to_world">
    <lookat origin="-1, 0.5, 2" target="0, 0, 0" up="0, 0, 1"/></transform>
  <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="30"/>
    <rfilter type="box"/></film>
</sensor>""",
]


def main():
    print(f"// Mitsuba {mi.__version__}, scalar_rgb (mitsuba_camera_reference.py)")
    print("const char* const kCameraXml[] = {")
    for xml in SENSORS:
        print(f'R"({xml})",')
    print("};")
    print("// sensor, film sample (x, y) in [0, 1]^2, ray origin, ray direction")
    print("const CameraReferenceRow kCameraRays[] = {")
    rng = np.random.default_rng(11)
    for index, xml in enumerate(SENSORS):
        sensor = mi.load_string(f'<scene version="3.0.0">{xml}</scene>').sensors()[0]
        samples = [(0.5, 0.5), (0.0, 0.0), (1.0, 1.0)] + [
            tuple(float(np.float32(u)) for u in rng.uniform(0, 1, 2)) for _ in range(5)]
        for sx, sy in samples:
            ray, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(sx, sy), mi.Point2f(0.5, 0.5))
            o, d = ray.o, ray.d
            print(f"  {{{index}, {{{sx!r}f, {sy!r}f}}, {{{o[0]!r}, {o[1]!r}, {o[2]!r}}}, "
                  f"{{{d[0]!r}, {d[1]!r}, {d[2]!r}}}}},")
    print("};")


if __name__ == "__main__":
    main()
