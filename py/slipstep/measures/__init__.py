"""What a result measures, numpy only (no files, no figures).

``contact_edges``  2D contact: profiles, half-widths, growth, force-displacement, path history
``contact_faces``  3D contact: profiles on faces, radii, mirror planes, contactor forces
``resultants``     contact and support resultants per increment (history.csv), drivers
``indentation``    Oliver-Pharr hardness and modulus of an unloading curve
``references``     closed forms: Hertz (line, sphere), effective moduli, Lamé
"""
