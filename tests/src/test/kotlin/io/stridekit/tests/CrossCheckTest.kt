package io.stridekit.tests

import io.stridekit.AccelSample
import io.stridekit.GnssFix
import io.stridekit.PaceException
import io.stridekit.PaceSample
import io.stridekit.PaceSource
import io.stridekit.PaceTracker
import io.stridekit.SensorStream
import io.stridekit.StepSample
import io.stridekit.TimeUnit
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.Test
import java.io.File
import kotlin.math.abs
import kotlin.test.assertEquals
import kotlin.test.assertFalse
import kotlin.test.assertTrue

/**
 * The mistakes of issue 36 made through the FFI, on real recordings of
 * `../shared/data` (skipped when absent): cadence in strides per minute pushed as steps
 * per minute, and timestamps in the wrong unit.
 */
class CrossCheckTest {
    private fun dataDir(): File? =
        (System.getenv("STRIDEKIT_DATA") ?: System.getProperty("stridekit.data"))
            ?.let { File(it) }
            ?.takeIf { it.isDirectory }

    /** One row of the shared pace CSVs: time, position, cadence per leg. */
    private data class Row(val tS: Double, val lat: Double?, val lon: Double?, val stridesPerMin: Double?)

    private fun run(name: String): List<Row>? {
        val file = dataDir()?.resolve("pace/csv/$name")
        assumeTrue(file?.isFile == true, "skipping: ../shared/data/pace/csv not found (set STRIDEKIT_DATA)")
        val lines = file!!.readLines()
        val header = lines.first().split(',')
        val col = { n: String -> header.indexOf(n) }
        val (t, lat, lon, strides) = listOf("t_unix_s", "lat_deg", "lon_deg", "cadence_strides_per_min").map(col)
        return lines.drop(1).map { line ->
            val f = line.split(',')
            Row(f[t].toDouble(), f[lat].toDoubleOrNull(), f[lon].toDoubleOrNull(), f[strides].toDoubleOrNull())
        }
    }

    /** Samples as a replay makes them: per row the cadence, then the fix; `k` steps per report, times × `timeScale`. */
    private fun samples(rows: List<Row>, k: Double, timeScale: Double = 1.0): List<PaceSample> {
        val t0 = rows.first().tS
        return rows.flatMap { r ->
            val t = (r.tS - t0) * timeScale
            listOfNotNull(
                r.stridesPerMin?.let { PaceSample.Steps(StepSample.Cadence(tS = t, stepsPerMin = k * it)) },
                if (r.lat != null && r.lon != null) PaceSample.Fix(GnssFix(tS = t, latDeg = r.lat, lonDeg = r.lon)) else null,
            )
        }
    }

    @Test
    fun `strides per minute pushed as steps are doubled and flagged, the distance right`() {
        val rows = run("runpandas_2020-12-02T06_08_29-300_Running.csv") ?: return
        val steps = PaceTracker.withDefaults().use { t -> t.pushSamples(samples(rows, 2.0)).latest!! }
        PaceTracker.withDefaults().use { t ->
            // FIT, TCX and Garmin's APIs call strides per minute "cadence".
            val r = t.pushSamples(samples(rows, 1.0))
            assertTrue(r.rejected.isEmpty(), "${r.rejected.take(3)}")
            val e = r.latest!!
            assertTrue(e.flags.cadenceDoubled, "${e.flags}")
            assertFalse(e.flags.cadenceMayBeStrides)
            // Before: 2 100 m against 6 899 m, source PEDOMETER with GNSS weight 0.
            val err = e.distanceM / steps.distanceM - 1.0
            assertTrue(abs(err) < 0.04, "${e.distanceM} m against ${steps.distanceM} m")
            assertTrue((e.cadenceSpm ?: 0.0) > 150.0, "cadence ${e.cadenceSpm} is for steps")
            assertFalse(steps.flags.cadenceDoubled, "the run as recorded is not doubled")
        }
    }

    @Test
    fun `fix and step times in milliseconds are refused, named once, and change nothing`() {
        val rows = run("runpandas_2020-12-02T06_08_29-300_Running.csv") ?: return
        PaceTracker.withDefaults().use { t ->
            val batch = samples(rows, 2.0, timeScale = 1000.0)
            val r = t.pushSamples(batch)
            val units = r.rejected.map { it.error }.map {
                assertTrue(it is PaceException.TimeNotInSeconds, "$it")
                val e = it as PaceException.TimeNotInSeconds
                e.stream to e.likelyUnit
            }.toSet()
            assertEquals(setOf(SensorStream.GNSS to TimeUnit.MILLISECONDS, SensorStream.STEPS to TimeUnit.MILLISECONDS), units)
            // The first samples of each stream are held (their unit unknown), never used.
            assertEquals(batch.size - 6, r.rejected.size)
            val e = t.estimate()!!
            assertEquals(0.0, e.distanceM)
            assertEquals(PaceSource.INITIALIZING, e.source)
        }
    }

    @Test
    fun `accelerometer times in milliseconds read as nanoseconds are named as such`() {
        val file = dataDir()?.resolve("steps/oxford/Samsung_Carmelo_Hard_BackPocket_1/accelerometer.csv")
        assumeTrue(file?.isFile == true, "skipping: ../shared/data not found (set STRIDEKIT_DATA)")
        // The column holds nanoseconds; as if it held milliseconds read as nanoseconds: ×10⁻⁶.
        val samples = file!!.readLines().take(3000).mapNotNull { line ->
            val f = line.split(',')
            if (f.size < 5) null else AccelSample(f[0].trim().toDouble() / 1e15, f[2].toDouble(), f[3].toDouble(), f[4].toDouble())
        }
        PaceTracker.withDefaults().use { t ->
            val r = t.pushAccelSamples(samples)
            val named = r.rejected.count { it.error is PaceException.TimeTooFine }
            // Before: every one a "duplicate timestamp" (TimeNotIncreasing).
            assertTrue(named >= 0.99 * samples.size, "$named of ${samples.size}: ${r.rejected.take(2)}")
            assertEquals(0L, t.detectedSteps().toLong())
        }
    }
}
