# The paper's helicopter (Figure 2): Combinatorial Geometry from simple
# bodies. The same model as the POV-Ray baseline scene helicopter21.pov
# (POV-Ray's left-handed y-up coordinates become our right-handed z-up:
# (x, y, z) -> (x, z, y)), except that the mast stops under the hub and
# the tail rotor hub stands clear of the fin, so the rotors share no body
# with the airframe and can spin on their own in the film. Nose along +x,
# main rotor mast on the z axis, tail rotor axis along y through
# (-9.45, y, 3.1). Ground at z = 0.
TITLE  Helicopter after Goldstein & Nagel (1971), Figure 2
UNITS  m

BODY fus      ELLG (0, 0, 2)      (3, 0, 0) (0, 1.3, 0) (0, 0, 1.25)    # fuselage
BODY belly    RPP  -4 4  -2 2  -1 1.15                                 # flat bottom cut
BODY canopyb  ELLG (1.7, 0, 2.35) (1.7, 0, 0) (0, 1.1, 0) (0, 0, 1.05)
BODY boom     TRC  (-2.4, 0, 2.3) (-6.8, 0, 0.4) 0.55 0.16             # tail boom
BODY finb     RAW  (-9.75, -0.07, 2.5) (0.775, 0, 0) (0, 0, 2.214286) (0, 0.14, 0)
BODY stab     RPP  -8.3 -7.6  -1.3 1.3  2.5 2.62                        # horizontal stabiliser
BODY mastb    RCC  (0, 0, 2.9) (0, 0, 0.95) 0.14                       # ends under the hub
BODY hubb     RCC  (0, 0, 3.85) (0, 0, 0.3) 0.42
BODY bladea   BOX  (-5.349561183, 2.251798207, 3.94) (10.51317033, -4.90237184, 0) (0.185952035, 0.398775426, 0) (0, 0, 0.08)
BODY bladeb   BOX  (2.251798207, 5.349561183, 3.94) (-4.90237184, -10.51317033, 0) (0.398775426, -0.185952035, 0) (0, 0, 0.08)
BODY thub     RCC  (-9.45, 0.07, 3.1) (0, 0.31, 0) 0.16                # clear of the fin
BODY tbladea  BOX  (-8.96062178, 0.26, 2.112372055) (-1.1, 0, 1.90525589) (0.12124356, 0, 0.07) (0, 0.06, 0)
BODY tbladeb  BOX  (-8.462372055, 0.26, 3.58937822) (-1.90525589, 0, -1.1) (-0.07, 0, 0.12124356) (0, 0.06, 0)
BODY skidl    RCC  (-2.6, -1.25, 0.1) (5, 0, 0) 0.09
BODY skidr    RCC  (-2.6, 1.25, 0.1) (5, 0, 0) 0.09
BODY sfl      RCC  (1.2, -1.25, 0.1) (-0.2, 0.5, 1.4) 0.07
BODY sfr      RCC  (1.2, 1.25, 0.1) (-0.2, -0.5, 1.4) 0.07
BODY srl      RCC  (-1.3, -1.25, 0.1) (0.2, 0.5, 1.4) 0.07
BODY srr      RCC  (-1.3, 1.25, 0.1) (0.2, -0.5, 1.4) 0.07
BODY cowl     RPP  -2.2 0.7  -0.65 0.65  2.7 3.45                       # engine cowling
BODY exo      RCC  (-1.9, 0, 3.1) (-1.1, 0, 0.15) 0.26                  # exhaust, outer
BODY exi      RCC  (-1.8, 0, 3.1) (-1.3, 0, 0.17) 0.18                  # exhaust, bore
BODY band     RPP  -1.6 0.3  -2 2  1.3 2.7                              # door and window band
BODY below21  HAF  (0, 0, 1) 2.1                                        # z <= 2.1
BODY below27  HAF  (0, 0, 1) 2.7                                        # z <= 2.7

REGION fuselage    = +fus -belly -canopyb -band -cowl COLOR 0.55 0.60 0.45 K 0.85
REGION door        = +fus +band +below21 -canopyb    COLOR 0.45 0.50 0.38 K 0.85
REGION window      = +fus +band -below21 -canopyb    COLOR 0.25 0.30 0.40 K 0.85
REGION canopy      = +canopyb -belly                 COLOR 0.35 0.45 0.60 K 0.85
REGION tailboom    = +boom -fus -cowl -stab          COLOR 0.55 0.60 0.45 K 0.85
REGION fin         = +finb -boom                     COLOR 0.55 0.60 0.45 K 0.85
REGION stabilizer  = +stab -boom                     COLOR 0.55 0.60 0.45 K 0.85
REGION mast        = +mastb -fus -cowl               COLOR 0.6 0.6 0.6 K 0.85
REGION hub         = +hubb                           COLOR 0.3 0.3 0.3 K 0.85
REGION blade_a     = +bladea -hubb                   COLOR 0.2 0.2 0.2 K 0.85
REGION blade_b     = +bladeb -hubb -bladea           COLOR 0.2 0.2 0.2 K 0.85
REGION tailhub     = +thub                           COLOR 0.3 0.3 0.3 K 0.85
REGION tailblade_a = +tbladea -thub                  COLOR 0.2 0.2 0.2 K 0.85
REGION tailblade_b = +tbladeb -thub -tbladea         COLOR 0.2 0.2 0.2 K 0.85
REGION skid_l      = +skidl                          COLOR 0.35 0.35 0.35 K 0.85
REGION skid_r      = +skidr                          COLOR 0.35 0.35 0.35 K 0.85
REGION strut_fl    = +sfl -skidl -fus                COLOR 0.35 0.35 0.35 K 0.85
REGION strut_fr    = +sfr -skidr -fus                COLOR 0.35 0.35 0.35 K 0.85
REGION strut_rl    = +srl -skidl -fus                COLOR 0.35 0.35 0.35 K 0.85
REGION strut_rr    = +srr -skidr -fus                COLOR 0.35 0.35 0.35 K 0.85
REGION cowling     = +cowl -fus                      COLOR 0.50 0.55 0.42 K 0.85
REGION exhaust     = +exo -exi -cowl                 COLOR 0.25 0.22 0.20 K 0.85
REGION fairing     = +cowl +fus -below27 -canopyb    COLOR 0.50 0.55 0.42 K 0.85
REGION stab_root   = +boom +stab                     COLOR 0.55 0.60 0.45 K 0.85

# POV-Ray's camera: location <9,6.5,-13> look_at <-1.6,2,0>, horizontal
# angle 46 degrees, i.e. 35.33 degrees vertical at 4:3.
CAMERA EYE (9, -13, 6.5) AT (-1.6, 0, 2.0) UP (0, 0, 1) FOV 35.33
LIGHT  SUN PARALLEL DIR (0.6, 1, -1.5) INTENSITY 1
AMBIENT 0.15
BACKGROUND 0.55 0.7 0.9
SIZE 960 720
