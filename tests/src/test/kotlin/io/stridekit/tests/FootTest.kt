package io.stridekit.tests

import io.stridekit.FootAxisRemap
import io.stridekit.FootConfig
import io.stridekit.FootCorrection
import io.stridekit.FootDetector
import io.stridekit.FootDetectorKind
import io.stridekit.FootEstimate
import io.stridekit.FootException
import io.stridekit.FootGyroTiming
import io.stridekit.FootNavigator
import io.stridekit.FootOutput
import io.stridekit.ImuSample
import io.stridekit.footAxesFromSpec
import io.stridekit.footAxesPyshoe
import io.stridekit.footConfigCalibratedImu
import io.stridekit.footConfigDefault
import io.stridekit.footDetectorDefault
import io.stridekit.footShippedSvmModel
import io.stridekit.packFootSamples
import io.stridekit.simulateClippedFootRun
import io.stridekit.simulateFootWalk
import org.junit.jupiter.api.Test
import java.io.File
import java.nio.ByteBuffer
import java.nio.ByteOrder
import kotlin.math.hypot
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertFailsWith
import kotlin.test.assertNotNull
import kotlin.test.assertNull
import kotlin.test.assertTrue

/** FootNavigator from Kotlin: a real walking trial, packed batches, typed errors, config. */
class FootTest {
    private companion object {
        const val SIM_SEED: ULong = 20_261_122uL
    }

    private fun dataDir(): File? =
        (System.getenv("STRIDEKIT_DATA") ?: System.getProperty("stridekit.data"))
            ?.let { File(it) }
            ?.takeIf { it.isDirectory }

    /** The documented 56-byte (6-axis) little-endian records: t, ax, ay, az, gx, gy, gz. */
    private fun pack(samples: List<ImuSample>): ByteArray {
        val b = ByteBuffer.allocate(samples.size * 56).order(ByteOrder.LITTLE_ENDIAN)
        for (s in samples) {
            b.putDouble(s.tS)
            b.putDouble(s.accelXMps2).putDouble(s.accelYMps2).putDouble(s.accelZMps2)
            b.putDouble(s.gyroXRads).putDouble(s.gyroYRads).putDouble(s.gyroZRads)
        }
        return b.array()
    }

    /** A foot at rest on a level floor, body axes = sensor axes (z up), 200 Hz. */
    private fun rest(n: Int, t0: Double = 0.0): List<ImuSample> =
        (0 until n).map { i ->
            ImuSample(
                tS = t0 + i * 0.005,
                accelXMps2 = 0.02, accelYMps2 = -0.01, accelZMps2 = 9.81,
                gyroXRads = 0.001, gyroYRads = -0.002, gyroZRads = 0.0005,
            )
        }

    private fun FootEstimate.horizontal() = hypot(positionM.east, positionM.north)

    /** A walk to push: its samples, the config for its axes, the truth's path length and end, where it comes from. */
    private class Walk(val samples: List<ImuSample>, val config: FootConfig, val truthPathM: Double, val truthEndM: Double, val name: String)

    /** The pyshoe trial 2017-11-22-11-37-47 (axes x fwd, y right, z down; VICON truth), or null when absent. */
    private fun realTrial(): Walk? {
        val file = dataDir()?.resolve("foot/pyshoe-vicon/2017-11-22-11-37-47.csv")?.takeIf { it.isFile } ?: return null
        // Header: t_s, acc_{x,y,z}_mps2, gyr_{x,y,z}_rads, gt_{x,y,z}_m, zv_*.
        val lines = file.readLines()
        val cols = lines.first().split(',').map { it.trim() }
        val idx = listOf("t_s", "acc_x_mps2", "acc_y_mps2", "acc_z_mps2", "gyr_x_rads", "gyr_y_rads", "gyr_z_rads")
            .map { name -> cols.indexOf(name).also { assertTrue(it >= 0, "column $name missing") } }
        val gt = listOf("gt_x_m", "gt_y_m").map { cols.indexOf(it) }
        val samples = ArrayList<ImuSample>(lines.size)
        val truth = ArrayList<Pair<Double, Double>>(lines.size)
        for (line in lines.drop(1)) {
            if (line.isBlank()) continue
            val f = line.split(',')
            val v = idx.map { f[it].toDouble() }
            samples.add(ImuSample(v[0], v[1], v[2], v[3], v[4], v[5], v[6]))
            truth.add(f[gt[0]].toDouble() to f[gt[1]].toDouble())
        }
        // Horizontal path length of the truth at ~10 Hz, for scale.
        var path = 0.0
        for (i in 20 until truth.size step 20) {
            path += hypot(truth[i].first - truth[i - 20].first, truth[i].second - truth[i - 20].second)
        }
        val end = hypot(truth.last().first - truth.first().first, truth.last().second - truth.first().second)
        return Walk(samples, footConfigDefault().copy(axisRemap = footAxesPyshoe()), path, end, file.name)
    }

    private fun unpack(bytes: ByteArray): List<ImuSample> {
        val b = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN)
        return (0 until bytes.size / 56).map {
            ImuSample(b.getDouble(), b.getDouble(), b.getDouble(), b.getDouble(), b.getDouble(), b.getDouble(), b.getDouble())
        }
    }

    @Test
    fun `a walk pushed in packed batches closes its loop`() {
        val walk = realTrial() ?: run {
            println("FootTest: ../shared/data/foot/pyshoe-vicon not found (set STRIDEKIT_DATA): skipping the real trial, using a simulated walk")
            val sim = simulateFootWalk(SIM_SEED, 2u)
            Walk(unpack(sim.samplesPacked), footConfigDefault(), sim.trueDistanceM, hypot(sim.trueEndM.east, sim.trueEndM.north), "simulated walk")
        }
        val samples = walk.samples
        FootNavigator(walk.config).use { nav ->
            val strides = mutableListOf<FootEstimate>()
            var produced = 0
            for (batch in samples.chunked(1000)) {
                val r = nav.pushPacked(pack(batch), FootOutput.STRIDE_ENDS)
                assertTrue(r.rejected.isEmpty(), "rejected: ${r.rejected.take(3)}")
                assertTrue(r.estimates.all { it.stride != null })
                strides += r.estimates
                produced += r.produced
            }
            assertTrue(nav.isAligned())
            assertEquals(200.0, nav.sampleRateHz(), 5.0)
            val end = assertNotNull(nav.estimate())
            assertTrue(produced.toInt() in (samples.size - 200)..samples.size, "produced $produced of ${samples.size}")
            assertEquals(end.strides.toInt(), strides.size, "one stride-end estimate per stride")
            // A bias jump needs two still stances: never more jumps than strides.
            assertTrue(nav.biasJumps() in 0L..end.strides.toLong(), "bias jumps ${nav.biasJumps()}")
            assertTrue(end.strides >= 20, "strides counted: ${end.strides}")
            // Every trial here is on a level floor: most strides are taken as level, and those report no climb.
            val levelled = strides.count { it.stride!!.levelledM != 0.0 }
            assertTrue(levelled * 2 > strides.size, "levelled $levelled of ${strides.size}")
            assertTrue(strides.all { it.stride!!.levelledM == 0.0 || it.stride!!.climbM == 0.0 })
            assertTrue(end.distanceM > 0.7 * walk.truthPathM && end.distanceM < 1.2 * walk.truthPathM,
                "distance ${end.distanceM} m vs truth path ${walk.truthPathM} m")
            val closure = end.horizontal() / end.distanceM
            println("FootTest: ${walk.name}: ${end.strides} strides, ${"%.2f".format(end.distanceM)} m (truth ${"%.2f".format(walk.truthPathM)} m), " +
                "end ${"%.3f".format(end.horizontal())} m from start (${"%.2f".format(100 * closure)} %; truth ${"%.3f".format(walk.truthEndM)} m)")
            // The default detector (adaptive SHOE) closes walking trials to 0.32 %
            // (median, 3-D, calibrated-IMU profile; docs/foot.md, `stridekit eval foot`);
            // the consumer defaults are used here; 5 % catches a broken pipeline
            // without asserting accuracy the detector does not have.
            assertTrue(closure < 0.05, "loop closure ${100 * closure} % of ${end.distanceM} m")
            assertTrue(listOf(end.positionM.east, end.velocityMps.up, end.yawRad).all { it.isFinite() })
            assertTrue(end.positionStdM.east > 0.0 && end.headingStdRad > 0.0)
        }

        // The same samples as records and one by one give the same estimates as packed.
        val head = samples.subList(0, 2000)
        val viaPacked = FootNavigator(walk.config).use { it.pushPacked(packFootSamples(head), FootOutput.ALL).estimates }
        val viaRecords = FootNavigator(walk.config).use { it.pushSamples(head, FootOutput.ALL).estimates }
        val oneByOne = FootNavigator(walk.config).use { nav -> head.mapNotNull { nav.push(it) } }
        assertEquals(viaPacked, viaRecords)
        assertEquals(viaPacked, oneByOne)
        assertContentEquals(pack(head), packFootSamples(head))
        // The foot navigator does not use the magnetometer fields of ImuSample.
        val withMag = head.map { it.copy(magXUt = 20.0, magYUt = 0.0, magZUt = -40.0) }
        assertContentEquals(packFootSamples(head), packFootSamples(withMag))
        val viaMag = FootNavigator(walk.config).use { it.pushSamples(withMag, FootOutput.ALL).estimates }
        assertEquals(viaRecords, viaMag)
    }

    @Test
    fun `a simulated walk gives Rust's estimates and resumes from a snapshot`() {
        val sim = simulateFootWalk(SIM_SEED, 1u)
        assertEquals(0, sim.referenceRejected)
        assertEquals(sim.sampleCount.toInt() * 56, sim.samplesPacked.size)
        val bytes = sim.samplesPacked
        val cut = bytes.size / 56 / 3 * 56
        FootNavigator.withDefaults().use { nav ->
            val first = nav.pushPacked(bytes.copyOfRange(0, cut), FootOutput.LATEST_ONLY)
            val saved = nav.snapshot()
            FootNavigator.restore(saved).use { again ->
                assertContentEquals(saved, again.snapshot())
                assertEquals(nav.config(), again.config())
                assertEquals(nav.estimate(), again.estimate())
                val rest = bytes.copyOfRange(cut, bytes.size)
                val a = nav.pushPacked(rest, FootOutput.ALL)
                val b = again.pushPacked(rest, FootOutput.ALL)
                assertEquals(a.estimates, b.estimates, "a restored navigator continues bit-identically")
                assertContentEquals(nav.snapshot(), again.snapshot())
                assertEquals(sim.referenceFinal, a.latest, "FFI path = Rust path")
                assertEquals(sim.referenceProduced, first.produced + a.produced)
            }
            val end = assertNotNull(nav.estimate())
            assertTrue(end.horizontal() < 0.03 * end.distanceM, "simulated loop closes: $end")
            assertEquals(sim.trueStrides.toDouble(), end.strides.toDouble(), 2.0)
        }
        assertFailsWith<FootException.InvalidSnapshot> { FootNavigator.restore(byteArrayOf(1, 2, 3)) }
        assertFailsWith<FootException.InvalidConfig> { simulateFootWalk(1uL, 0u) }
    }

    @Test
    fun `bad samples are typed exceptions and change nothing`() {
        FootNavigator.withDefaults().use { nav ->
            assertNull(nav.estimate())
            val first = nav.pushSamples(rest(200), FootOutput.LATEST_ONLY)
            assertTrue(first.rejected.isEmpty())
            assertTrue(nav.isAligned())
            val before = assertNotNull(nav.estimate())
            val saved = nav.snapshot()
            val last = rest(200).last()

            val nan = assertFailsWith<FootException.NonFinite> { nav.push(last.copy(tS = 1.0, accelYMps2 = Double.NaN)) }
            assertEquals("accel_y_mps2", nan.field)
            assertFailsWith<FootException.NonFinite> { nav.push(last.copy(tS = Double.POSITIVE_INFINITY)) }
            val back = assertFailsWith<FootException.TimeNotIncreasing> { nav.push(last.copy(tS = 0.5)) }
            assertEquals(0.5, back.tS)
            assertEquals(last.tS, back.lastTS)
            assertFailsWith<FootException.TimeNotIncreasing> { nav.push(last) }
            val big = assertFailsWith<FootException.OutOfRange> { nav.push(last.copy(tS = 1.0, gyroZRads = 500.0)) }
            assertEquals("gyro_z_rads", big.field)
            assertFailsWith<FootException.InvalidBuffer> { nav.pushPacked(ByteArray(55), FootOutput.ALL) }
            assertEquals(before, nav.estimate())
            assertContentEquals(saved, nav.snapshot(), "rejections change nothing")

            // In a batch, bad samples are reported by index and skipped.
            val more = rest(100, t0 = 1.0).toMutableList()
            more[10] = more[10].copy(gyroXRads = Double.NaN)
            more[20] = more[20].copy(tS = 0.2)
            val r = nav.pushPacked(pack(more), FootOutput.ALL)
            assertEquals(listOf(10, 20), r.rejected.map { it.index })
            assertTrue(r.rejected[0].error is FootException.NonFinite, "${r.rejected[0].error}")
            assertTrue(r.rejected[1].error is FootException.TimeNotIncreasing, "${r.rejected[1].error}")
            assertTrue(r.rejected[1].reason.contains("not after"), r.rejected[1].reason)
            assertEquals(r.latest, nav.estimate())
        }

        // A navigator that saw rejected samples continues exactly like one that never did.
        val good = rest(400)
        val withBad = good.flatMapIndexed { i, s ->
            if (i % 50 == 25) listOf(s.copy(accelZMps2 = Double.NaN), s, s) else listOf(s)
        }
        val clean = FootNavigator.withDefaults().use { it.pushSamples(good, FootOutput.ALL) }
        val noisy = FootNavigator.withDefaults().use { it.pushSamples(withBad, FootOutput.ALL) }
        assertEquals(8 * 2, noisy.rejected.size)
        assertEquals(clean.estimates, noisy.estimates)
        assertEquals(clean.latest, noisy.latest)

        // Accelerations in g are refused while aligning.
        FootNavigator.withDefaults().use { nav ->
            val fresh = nav.snapshot()
            val g = rest(1).first().copy(accelZMps2 = 1.0)
            val e = assertFailsWith<FootException.AccelerationNotInMps2> { nav.push(g) }
            assertContentEquals(fresh, nav.snapshot())
            assertEquals(1.0, e.meanMagnitude, 0.01)
            assertTrue(e.toString().contains("9.80665"), e.toString())
        }
    }

    @Test
    fun `configuration defaults, validation and round trip`() {
        val adaptiveShoe = footDetectorDefault(FootDetectorKind.ADAPTIVE_SHOE)
        assertEquals(
            footConfigDefault(),
            FootConfig(detector = adaptiveShoe, correction = FootCorrection.FULL, gyroTiming = FootGyroTiming.INSTANTANEOUS),
        )
        assertTrue(adaptiveShoe is FootDetector.AdaptiveShoe, "$adaptiveShoe")
        FootNavigator.withDefaults().use { assertEquals(footConfigDefault(), it.config()) }
        val svmAdaptive = footDetectorDefault(FootDetectorKind.SVM_ADAPTIVE)
        assertTrue(svmAdaptive is FootDetector.SvmAdaptive && svmAdaptive.modelText == null, "$svmAdaptive")

        // The industrial-IMU profile and axes from a text spec.
        val calibrated = footConfigCalibratedImu()
        assertEquals(FootGyroTiming.INTERVAL_MEAN, calibrated.gyroTiming)
        assertEquals(false, calibrated.gyroBiasFromAlignment)
        FootNavigator(calibrated).use { assertEquals(calibrated, it.config()) }
        assertEquals(footAxesPyshoe(), footAxesFromSpec("frd"))
        assertEquals(footAxesPyshoe(), footAxesFromSpec("x,-y,-z"))
        assertEquals(FootAxisRemap(), footAxesFromSpec("flu"))
        val badAxes = assertFailsWith<FootException.InvalidConfig> { footAxesFromSpec("x,y,-z") }
        assertEquals("axes", badAxes.field)

        val svm = footConfigDefault().copy(
            axisRemap = footAxesPyshoe(),
            detector = footDetectorDefault(FootDetectorKind.SVM),
            correction = FootCorrection.AS_PUBLISHED,
            medianWindow = 3,
            gyroRangeRads = 35.0,
        )
        assertEquals(FootDetector.Svm(modelText = null), svm.detector)
        FootNavigator(svm).use { assertEquals(svm, it.config()) }
        // The shipped model passed as text is the shipped model.
        FootNavigator(svm.copy(detector = FootDetector.Svm(footShippedSvmModel()))).use { assertEquals(svm, it.config()) }
        for (kind in FootDetectorKind.values()) {
            val c = footConfigDefault().copy(detector = footDetectorDefault(kind))
            FootNavigator(c).use { assertEquals(c, it.config()) }
        }

        val even = assertFailsWith<FootException.InvalidConfig> { FootNavigator(footConfigDefault().copy(medianWindow = 4)) }
        assertEquals("median_window", even.field)
        assertFailsWith<FootException.InvalidConfig> { FootNavigator(footConfigDefault().copy(zuptNoiseMps = -1.0)) }
        // Zero-velocity updates bounded at a normalised innovation of 100 by default; null: the paper's face value.
        assertEquals(100.0, footConfigDefault().zuptGateNis)
        assertFailsWith<FootException.InvalidConfig> { FootNavigator(footConfigDefault().copy(zuptGateNis = 0.0)) }
        FootNavigator(footConfigDefault().copy(zuptGateNis = null)).use { assertEquals(null, it.config().zuptGateNis) }
        // The accelerometer-to-gyroscope alignment (a device calibration): zero by default, within ±0.1 rad.
        assertEquals(0.0, footConfigDefault().accelAlignmentYRad)
        val aligned = footConfigDefault().copy(accelAlignmentYRad = 0.021)
        FootNavigator(aligned).use { assertEquals(aligned, it.config()) }
        val tooFar = assertFailsWith<FootException.InvalidConfig> { FootNavigator(footConfigDefault().copy(accelAlignmentXRad = 0.2)) }
        assertEquals("accel_alignment_rad", tooFar.field)
        // The level floor: strides within 5 % of level are taken as level by default; null turns it off.
        assertEquals(0.05, footConfigDefault().levelStrideMaxGrade)
        FootNavigator(footConfigDefault().copy(levelStrideMaxGrade = null)).use { assertEquals(null, it.config().levelStrideMaxGrade) }
        val steep = assertFailsWith<FootException.InvalidConfig> { FootNavigator(footConfigDefault().copy(levelStrideMaxGrade = 0.3)) }
        assertEquals("level_stride_max_grade", steep.field)
        assertFailsWith<FootException.InvalidConfig> { FootNavigator(footConfigDefault().copy(maxGapS = Double.NaN)) }
        val mirror = assertFailsWith<FootException.InvalidConfig> {
            FootNavigator(footConfigDefault().copy(axisRemap = footAxesPyshoe().copy(negateZ = false)))
        }
        assertEquals("axis_remap", mirror.field)
        val fixed = footDetectorDefault(FootDetectorKind.FIXED) as FootDetector.Fixed
        assertFailsWith<FootException.InvalidConfig> {
            FootNavigator(footConfigDefault().copy(detector = FootDetector.Fixed(fixed.thresholds.copy(gyroRads = 0.0))))
        }
        assertFailsWith<FootException.InvalidModel> {
            FootNavigator(footConfigDefault().copy(detector = FootDetector.Svm("stridekit-zupt-svm 1\nsvm acc_x")))
        }
    }

    @Test
    fun `a clipped accelerometer's ceiling is read after packed batches`() {
        // A two-lap simulated run, every accelerometer axis clipped at 70 % of its largest magnitude.
        val run = simulateClippedFootRun(SIM_SEED, 2u, 0.7)
        assertTrue(run.clippedValues > 1000, "clipped values ${run.clippedValues}")
        val bytes = run.samplesPacked
        FootNavigator(footConfigDefault()).use { nav ->
            assertNull(nav.accelCeilingMps2(), "no ceiling before any sample")
            var rejected = 0
            for (start in bytes.indices step 56 * 1000) {
                val batch = bytes.copyOfRange(start, minOf(bytes.size, start + 56 * 1000))
                rejected += nav.pushPacked(batch, FootOutput.STRIDE_ENDS).rejected.size
            }
            assertEquals(0, rejected)
            val ceiling = assertNotNull(nav.accelCeilingMps2(), "the ceiling is found")
            assertEquals(run.clipMps2, ceiling, 0.01 * run.clipMps2)
            assertEquals(run.referenceCeilingMps2, ceiling, "the FFI path gives Rust's ceiling")
        }
        // The same run unclipped never reaches a ceiling; an app that knows its range gets 99 % of it at once.
        val clean = simulateClippedFootRun(SIM_SEED, 2u, 1.0)
        FootNavigator(footConfigDefault()).use { nav ->
            nav.pushPacked(clean.samplesPacked, FootOutput.LATEST_ONLY)
            assertNull(nav.accelCeilingMps2(), "a run within range does not clip")
        }
        FootNavigator(footConfigDefault().copy(accelRangeMps2 = 156.9)).use { nav ->
            assertEquals(0.99 * 156.9, assertNotNull(nav.accelCeilingMps2()), 1e-9)
        }
    }
}
