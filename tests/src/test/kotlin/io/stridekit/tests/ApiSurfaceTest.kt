package io.stridekit.tests

import io.stridekit.AccelSample
import io.stridekit.FootNavigator
import io.stridekit.FootOutput
import io.stridekit.GnssFix
import io.stridekit.OrientationFilter
import io.stridekit.OrientationOutput
import io.stridekit.PhoneOdometry
import io.stridekit.PlacementClassifier
import io.stridekit.defaultPaceConfig
import io.stridekit.packFixes
import io.stridekit.ImuSample
import io.stridekit.NavException
import io.stridekit.PaceConfig
import io.stridekit.PaceException
import io.stridekit.PaceMode
import io.stridekit.PaceSource
import io.stridekit.PaceTracker
import io.stridekit.PhoneNavigator
import io.stridekit.StepDetectorMode
import io.stridekit.StepLengthModel
import io.stridekit.StepOrigin
import io.stridekit.StepSample
import io.stridekit.navigatorConfigDefault
import io.stridekit.packAccelSamples
import io.stridekit.packFootSamples
import io.stridekit.packImuSamples
import org.junit.jupiter.api.Test
import java.nio.ByteBuffer
import java.nio.ByteOrder
import kotlin.math.PI
import kotlin.math.sin
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertFailsWith
import kotlin.test.assertNotNull
import kotlin.test.assertNull
import kotlin.test.assertTrue

/** The surface an app meets: pack helpers, config records, Int/Long counts, nullability. */
class ApiSurfaceTest {
    private fun walk(seconds: Double): List<ImuSample> = (0 until (seconds * 100).toInt()).map { i ->
        val t = i / 100.0
        val bounce = 2.5 * sin(2 * PI * 1.8 * t)
        ImuSample(
            tS = t, accelXMps2 = 0.0, accelYMps2 = 0.3 * bounce, accelZMps2 = 9.81 + bounce,
            gyroXRads = 0.0, gyroYRads = 0.0, gyroZRads = 0.0,
            magXUt = 20.0, magYUt = 0.0, magZUt = -40.0,
        )
    }

    @Test
    fun `packImuSamples and packFootSamples write one layout family, accel before gyro`() {
        val s = ImuSample(
            tS = 1.5, accelXMps2 = 0.1, accelYMps2 = 0.2, accelZMps2 = 9.8,
            gyroXRads = 0.01, gyroYRads = 0.02, gyroZRads = 0.03,
        )
        val b = ByteBuffer.allocate(80).order(ByteOrder.LITTLE_ENDIAN)
        listOf(1.5, 0.1, 0.2, 9.8, 0.01, 0.02, 0.03, Double.NaN, Double.NaN, Double.NaN).forEach { b.putDouble(it) }
        assertContentEquals(b.array(), packImuSamples(listOf(s)))
        // The 56-byte record is the 80-byte one without the magnetometer (which the foot
        // layout never carries).
        val withMag = s.copy(magXUt = 20.0, magYUt = 0.0, magZUt = -40.0)
        assertContentEquals(b.array().copyOf(56), packFootSamples(listOf(withMag)))
        assertContentEquals(packImuSamples(listOf(withMag)).copyOf(56), packFootSamples(listOf(s)))

        val a = AccelSample(tS = 2.0, xMps2 = 1.0, yMps2 = -2.0, zMps2 = 9.0)
        val ab = ByteBuffer.allocate(32).order(ByteOrder.LITTLE_ENDIAN)
        listOf(2.0, 1.0, -2.0, 9.0).forEach { ab.putDouble(it) }
        assertContentEquals(ab.array(), packAccelSamples(listOf(a)))
    }

    @Test
    fun `every batch result counts the same way - accepted plus rejected is the batch`() {
        // One bad sample (a NaN time) in the middle of each batch.
        val imu = walk(12.0).toMutableList().also { it[300] = it[300].copy(tS = Double.NaN) }
        val n = imu.size
        fun check(name: String, accepted: Int, produced: Int, rejected: List<Int>) {
            assertEquals(listOf(300), rejected, "$name: rejected indices")
            assertEquals(n - 1, accepted, "$name: accepted")
            assertTrue(produced in 1..accepted, "$name: produced $produced of $accepted")
        }
        PhoneNavigator(navigatorConfigDefault()).use { e ->
            val r = e.pushImuPacked(packImuSamples(imu))
            check("PhoneNavigator", r.accepted, r.produced, r.rejected.map { it.index })
            assertEquals(r.accepted, r.produced, "one estimate per accepted sample")
        }
        OrientationFilter.withDefaults().use { e ->
            val r = e.pushImuPacked(packImuSamples(imu), OrientationOutput.LATEST_ONLY)
            check("OrientationFilter", r.accepted, r.produced, r.rejected.map { it.index })
            assertTrue(r.estimates.isEmpty(), "LATEST_ONLY returns no list")
        }
        PhoneOdometry.withDefaults().use { e ->
            val r = e.pushImuPacked(packImuSamples(imu))
            check("PhoneOdometry", r.accepted, r.produced, r.rejected.map { it.index })
        }
        PlacementClassifier.withDefaults().use { e ->
            val accel = imu.map { AccelSample(tS = it.tS, xMps2 = it.accelXMps2, yMps2 = it.accelYMps2, zMps2 = it.accelZMps2) }
            val r = e.pushAccelPacked(packAccelSamples(accel))
            check("PlacementClassifier", r.accepted, r.produced, r.rejected.map { it.index })
        }
        FootNavigator.withDefaults().use { e ->
            val rest = imu.map { it.copy(accelYMps2 = 0.0, accelZMps2 = 9.81) }
            val r = e.pushPacked(packFootSamples(rest), FootOutput.LATEST_ONLY)
            check("FootNavigator", r.accepted, r.produced, r.rejected.map { it.index })
        }
        PaceTracker(defaultPaceConfig()).use { e ->
            val fixes = (0 until n).map { i ->
                GnssFix(tS = if (i == 300) Double.NaN else i.toDouble(), latDeg = 52.0 + i * 1e-5, lonDeg = 21.0, horizontalAccuracyM = 5.0)
            }
            val r = e.pushFixesPacked(packFixes(fixes))
            check("PaceTracker", r.accepted, r.produced, r.rejected.map { it.index })
            assertEquals(r.produced, r.estimates.size, "one estimate per accepted fix, all returned")
        }
    }

    @Test
    fun `steps filled across dropped samples say so`() {
        // 30 s of walking with 1.2 s of samples dropped (a busy phone): the steps the
        // gap hid are counted at the cadence and flagged; every other step was seen.
        val gap = 15.0..16.2
        val samples = walk(30.0).filter { it.tS !in gap }
        PhoneNavigator.withDefaults().use { nav ->
            val steps = nav.pushImuPacked(packImuSamples(samples)).steps
            assertTrue(steps.size > 20, "steps ${steps.size}")
            val filled = steps.filter { it.origin != StepOrigin.DETECTED }
            assertTrue(filled.isNotEmpty(), "no step filled into the gap")
            for (s in filled) {
                assertEquals(StepOrigin.FILLED_ACROSS_GAP, s.origin)
                assertTrue(s.tS in 14.4..16.8, "filled at ${s.tS} s, off the gap")
            }
        }
    }

    @Test
    fun `a configured navigator walks from packed helper records`() {
        val config = navigatorConfigDefault().copy(priorPendulumK = 2.5)
        assertEquals(StepDetectorMode.ROBUST, config.stepDetector)
        assertEquals(StepLengthModel.PENDULUM, config.stepLengthModel)
        PhoneNavigator(config).use { nav ->
            assertNull(nav.estimate(), "null before the first sample")
            assertEquals(config, nav.config())
            val r = nav.pushImuPacked(packImuSamples(walk(20.0)))
            assertTrue(r.rejected.isEmpty(), "${r.rejected.take(2)}")
            val e = assertNotNull(r.latest)
            assertTrue(e.steps > 10L, "steps ${e.steps}")
        }
        // A platform-calibrated gyroscope by default; a raw one is said so, and kept.
        assertTrue(navigatorConfigDefault().gyroCalibrated)
        val raw = navigatorConfigDefault().copy(gyroCalibrated = false)
        PhoneNavigator(raw).use { nav -> assertEquals(raw, nav.config()) }
        val bad = navigatorConfigDefault().let { it.copy(orientation = it.orientation.copy(accelTimeConstantS = -1.0)) }
        assertFailsWith<NavException.InvalidConfig> { PhoneNavigator(bad) }
    }

    @Test
    fun `indices are Int, counts Long, and a negative count is typed`() {
        PaceTracker.withDefaults().use { t ->
            assertNull(t.estimate(), "null before the first sample")
            val r = t.pushStepSamples(
                listOf(
                    StepSample.Count(tS = 1.0, steps = 10L),
                    StepSample.Count(tS = 2.0, steps = -5L),
                    StepSample.Count(tS = 3.0, steps = 13L),
                ),
            )
            assertEquals(listOf(1), r.rejected.map { it.index })
            val err = r.rejected[0].error
            assertTrue(err is PaceException.OutOfRange && err.field == "steps", "$err")
            assertNotNull(t.estimate())
            assertNotNull(r.latest)
            assertFailsWith<PaceException.OutOfRange> { t.pushSteps(StepSample.Count(tS = 4.0, steps = -1L)) }
        }
    }

    @Test
    fun `pedometer speed without GNSS reports the step length it uses`() {
        PaceTracker(PaceConfig(mode = PaceMode.ADAPTIVE)).use { t ->
            for (i in 1..30) t.pushSteps(StepSample.Count(tS = i.toDouble(), steps = (170.0 / 60.0 * i).toLong()))
            val e = assertNotNull(t.estimate())
            assertEquals(PaceSource.PEDOMETER, e.source)
            val l = assertNotNull(e.stepLengthM, "a PEDOMETER speed comes with its step length")
            val cadenceHz = assertNotNull(e.cadenceSpm) / 60.0
            assertTrue(Math.abs(e.speedMps - cadenceHz * l) < 0.1 * e.speedMps, "speed ${e.speedMps} vs $cadenceHz × $l")
        }
    }
}
