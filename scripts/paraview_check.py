# Opens OUT/results.pvd with ParaView's own reader (headless, pvbatch) and prints the frame
# times, counts, arrays and the z-velocity range of three frames: proof that ParaView plays
# the series. Debian's python3-paraview conflicts with libvtk9-dev, so extract it instead:
#   cd /tmp && apt-get download python3-paraview && dpkg-deb -x python3-paraview_*_amd64.deb /opt/pvpy
#   PYTHONPATH=/opt/pvpy/usr/lib/python3/dist-packages pvbatch scripts/paraview_check.py OUT/results.pvd
import sys
from paraview.simple import *
r = PVDReader(FileName=sys.argv[1])
times = r.TimestepValues
print("timesteps", len(times), times[0], times[-1])
for t in (times[0], times[len(times)//2], times[-1]):
    r.UpdatePipeline(t)
    d = servermanager.Fetch(r)
    print(t, d.GetNumberOfCells(), d.GetNumberOfPoints(), [d.GetPointData().GetArrayName(i) for i in range(d.GetPointData().GetNumberOfArrays())], [d.GetCellData().GetArrayName(i) for i in range(d.GetCellData().GetNumberOfArrays())])
    rng = d.GetPointData().GetArray("velocity").GetRange(2)
    print("  vz range", rng)
