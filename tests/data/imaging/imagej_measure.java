// How the *_imagej.csv references were made (not built by shapepress):
//   cp imagej_measure.java Measure.java && javac -cp /usr/share/java/ij.jar Measure.java
//   java -Djava.awt.headless=true -cp /usr/share/java/ij.jar:. Measure IMAGE.pgm OUT.csv 128
import ij.*; import ij.process.*; import ij.measure.*; import ij.plugin.filter.*;
public class Measure {
  public static void main(String[] a) throws Exception {
    ImagePlus imp = IJ.openImage(a[0]);
    ImageProcessor ip = imp.getProcessor();
    ip.setThreshold(Double.parseDouble(a[2]), 255, ImageProcessor.NO_LUT_UPDATE);
    ResultsTable rt = new ResultsTable();
    int m = Measurements.AREA|Measurements.PERIMETER|Measurements.SHAPE_DESCRIPTORS|Measurements.FERET|Measurements.CENTROID|Measurements.ELLIPSE;
    ParticleAnalyzer pa = new ParticleAnalyzer(ParticleAnalyzer.EXCLUDE_EDGE_PARTICLES, m, rt, 0, Double.POSITIVE_INFINITY);
    pa.setHideOutputImage(true);
    pa.analyze(imp, ip);
    rt.setDecimalPlaces(0, 6);
    rt.saveAs(a[1]);
  }
}
