// Converts a colour image to 8-bit gray as ImageJ does (Image > Type > 8-bit, the unweighted mean
// of R, G and B) and saves it as PNG (ImageJ 1.53t, Debian 12 package imagej), for the gray PNGs
// of README.md:
//   xvfb-run -a imagej -b to_8bit.ijm IN,OUT.png
args = split(getArgument(), ",");
open(args[0]);
run("8-bit");
saveAs("PNG", args[1]);
