# The threads each test uses, for `ctest -j` (PROCESSORS): read by ctest after every suite's
# discovered tests (TEST_INCLUDE_FILES, tests/CMakeLists.txt). Every test runs with
# OMP_NUM_THREADS=1 and declares one processor; the ones below use two, because they pass
# --threads 2 to the binary, run two child processes at once (advise), or compare one thread
# with two in process (omp_set_num_threads(2)). A new test that uses more threads adds its
# name here.
set(shapepress_two_thread_tests
  "^analysis\\.ReportE2e\\.RealPlateAndCompactRunsOverlaid$"
  "^geometry\\.GenerateResume\\.KilledThreeTimesEndsAsTheUninterruptedRun$"
  "^geometry\\.Targets/GenerateCheckpoint\\.StoppedInEveryPhaseAndResumedFromTheFilesIsTheWholeRun/"
  "^imaging\\.ShapeStatsCli\\.MixedBatchProcessesTheGoodImages$"
  "^scenarios\\.AdviseCli\\."
  "^scenarios\\.AdviseCompactionCli\\."
  "^scenarios\\.BodyBedCli\\.(PressesAndUnloadsABondedBed|MassScalingMovesTheCurveByLessThanTwoPercent|PressesABedOfRigidClumps)$"
  "^scenarios\\.PlateResume\\."
  "^scenarios\\.(Determinism|BodyBedDeterminism|MulticontactDeterminism|MdrDeterminism|BmsDeterminism)\\."
  "^scenarios\\.BmsFills\\."
  "^scenarios\\.Clump\\.(OneAndTwoThreadsGiveTheSameBits|RestartFromSnapshotContinuesWithTheSameBits)$"
  "^scenarios\\.ListRebuild\\.NoContactIsMissedWhileAFastPunchStrainsTheBed$"
  "^scenarios\\.CompactionCalibration\\."
  "^pipelines\\.CalibratedBondsBed\\."
  "^pipelines\\.(AvicelSpheresStudy|Demo)\\."
  "^simulate\\.Engine\\.SameBitsForOneAndTwoThreads$"
  "^simulate\\.BondBreakage\\.APartlyBrokenBodyRestartsBitIdenticallyAndShowsItsBrokenBonds$")

foreach(label IN ITEMS unit validation e2e)
  foreach(stage IN ITEMS common app pipelines imaging geometry simulate packing scenarios analysis fem)
    foreach(test IN LISTS ${label}_${stage}_TESTS)
      foreach(pattern IN LISTS shapepress_two_thread_tests)
        if(test MATCHES "${pattern}")
          set_tests_properties("${test}" PROPERTIES PROCESSORS 2)
        endif()
      endforeach()
    endforeach()
  endforeach()
endforeach()
