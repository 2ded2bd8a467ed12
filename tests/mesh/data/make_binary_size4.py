"""Writes binary_size4.msh: binary MSH 4.1 as a writer with a 4-byte size_t would (Gmsh on a
32-bit machine): one unit-cube hexahedron, no $Entities. Gmsh on 64-bit machines writes only
8-byte size_t, so this file is made by hand from the MSH 4.1 layout (Gmsh reference manual)."""
import struct

I = lambda *v: struct.pack("<%di" % len(v), *v)   # int
S = lambda *v: struct.pack("<%dI" % len(v), *v)   # 4-byte size_t
D = lambda *v: struct.pack("<%dd" % len(v), *v)   # double
corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
out = b"$MeshFormat\n4.1 1 4\n" + I(1) + b"\n$EndMeshFormat\n"
out += b"$Nodes\n" + S(1, 8, 1, 8) + I(3, 1, 0) + S(8) + S(*range(1, 9))
out += b"".join(D(*c) for c in corners) + b"\n$EndNodes\n"
out += b"$Elements\n" + S(1, 1, 1, 1) + I(3, 1, 5) + S(1) + S(1, *range(1, 9)) + b"\n$EndElements\n"
open("binary_size4.msh", "wb").write(out)
