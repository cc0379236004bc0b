# Figure 3 of the paper: geometric ray tracing. Body 1 encloses everything;
# body 2 is a sphere and body 3 a cylinder that pierces it.
#   A = +2 -3   (the sphere outside the cylinder)
#   B = +3      (the cylinder)
#   C = +1 -2 -3 (the rest of the enclosure, where the camera stands)
# The camera stands at P0 inside the transparent region C. A ray along +x
# enters body 3 (E3, region B), then the sphere (E2, still B), leaves the
# cylinder (L3, into A), leaves the sphere (L2, back into C) and finally
# body 1 (L1, out of the geometry). Try:
#   synthavision shoot examples/figure3/figure3.sv --from -9,0,0 --dir 1,0,0
TITLE  Figure 3: Geometric ray tracing
UNITS  in

BODY 1 RPP -10 10  -10 10  -10 10
BODY 2 SPH (0, 0, 0) 3
BODY 3 RCC (-6, 0, 0) (6, 0, 0) 1

REGION A = +2 -3        COLOR 0.9 0.7 0.4  K 0.9
REGION B = +3           COLOR 0.4 0.6 0.9  K 0.9 TRANSPARENT
REGION C = +1 -2 -3     TRANSPARENT

CAMERA EYE (-9, -6, 5) AT (0, 0, 0) UP (0, 0, 1) FOV 50
LIGHT  SUN PARALLEL DIR (1, 1.5, -2) INTENSITY 0.9
AMBIENT 0.1
BACKGROUND 0.05
SIZE 720 540
