// Saves the binary masks of ImageJ's Watershed for the *_ij_mask.png / *_ij_ws.png files beside
// this macro: the mask as Convert to Mask makes it and the same mask after Process > Binary >
// Watershed (ImageJ 1.53t, Debian 12 package imagej), as imagej_analyze.ijm runs them, from this
// folder:
//   xvfb-run -a imagej -b imagej_watershed_mask.ijm IMAGE,STEM,BACKGROUND
// BACKGROUND "dark" ticks "Dark background". Particles are black (inverting lookup table).
args = split(getArgument(), ",");
open(args[0]);
if (bitDepth() != 8) run("8-bit");
if (args[2] == "dark") setAutoThreshold("Default dark"); else setAutoThreshold("Default");
setOption("BlackBackground", false);
run("Convert to Mask");
saveAs("PNG", args[1] + "_ij_mask.png");
run("Watershed");
saveAs("PNG", args[1] + "_ij_ws.png");
