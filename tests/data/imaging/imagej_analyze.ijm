// ImageJ's Analyze Particles as a user runs it, for the *_ij_*.csv files beside this macro
// (ImageJ 1.53t, Debian 12 package imagej; it needs a display, hence xvfb-run), from this folder:
//   xvfb-run -a imagej -batch imagej_analyze.ijm IMAGE,OUT.csv,WATERSHED,BACKGROUND,MINSIZE
// WATERSHED 1 runs Process > Binary > Watershed; BACKGROUND "dark" ticks "Dark background"
// (bright particles); MINSIZE in px, as shape-stats --min-area.
args = split(getArgument(), ",");
open(args[0]);
if (bitDepth() != 8) run("8-bit");
if (args[3] == "dark") setAutoThreshold("Default dark"); else setAutoThreshold("Default");
getThreshold(lower, upper);
print(getTitle() + ": ImageJ " + getVersion() + ", Default threshold " + lower + "-" + upper);
setOption("BlackBackground", false);
run("Convert to Mask");
if (args[2] == "1") run("Watershed");
run("Set Measurements...", "area centroid perimeter fit shape feret's redirect=None decimal=6");
run("Analyze Particles...", "size=" + args[4] + "-Infinity display exclude clear include");
saveAs("Results", args[1]);
