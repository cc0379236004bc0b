# A simple ground-level gun emplacement for the helicopter film, and the
# ground itself. The barrel pivots at (60, 30, 1.5) and points along -x.
UNITS m

BODY ground   RPP  -300 300  -300 300  -0.5 0
BODY pad      RCC  (60, 30, 0) (0, 0, 0.4) 3
BODY pedestal RCC  (60, 30, 0.4) (0, 0, 0.9) 0.5
BODY turret   SPH  (60, 30, 1.5) 0.55
BODY barrel   RCC  (59.5, 30, 1.5) (-4.5, 0, 0) 0.14
BODY bore     RCC  (59.4, 30, 1.5) (-4.7, 0, 0) 0.07
BODY sand     TOR  (60, 30, 0.4) (0, 0, 1) 3.2 0.45

REGION ground     = +ground -pad -sand   COLOR 0.42 0.50 0.30 K 0.9
REGION gun_base   = +pad OR +pedestal OR +turret OR +sand -pad   COLOR 0.45 0.45 0.40 K 0.85
REGION gun_barrel = +barrel -bore        COLOR 0.25 0.25 0.25 K 0.85
