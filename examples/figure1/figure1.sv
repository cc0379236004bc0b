# Figure 1 of the paper: a sphere (body 1) and a cylinder (body 2) that
# overlap, and the five regions they can form, side by side:
#   B = +1   C = +2   D = +1 -2   E = +2 -1   F = +1 +2
# The same scene as the POV-Ray baseline seed_fig1.pov.
TITLE  Figure 1: Examples of the Combinatorial Geometry method
UNITS  in

BODY 1  SPH (-6, 0, 0) 1
BODY 2  RCC (-2.55, -0.2, -1.4) (0, 0, 2.8) 0.6
BODY 1d SPH (0, 0, 0) 1
BODY 2d RCC (0.45, -0.2, -1.4) (0, 0, 2.8) 0.6
BODY 1e SPH (3, 0, 0) 1
BODY 2e RCC (3.45, -0.2, -1.4) (0, 0, 2.8) 0.6
BODY 1f SPH (6, 0, 0) 1
BODY 2f RCC (6.45, -0.2, -1.4) (0, 0, 2.8) 0.6

REGION B = +1         K 0.85
REGION C = +2         K 0.85
REGION D = +1d -2d    K 0.85
REGION E = +2e -1e    K 0.85
REGION F = +1f +2f    K 0.85

CAMERA EYE (0, -15, 4) AT (0, 0, 0) UP (0, 0, 1) FOV 41.80
LIGHT  SUN PARALLEL DIR (1, 1, -1.5) INTENSITY 1
AMBIENT 0.15
BACKGROUND 0
SIZE 960 720
