package io.stridekit.robolectric

import org.junit.Assume.assumeTrue
import java.io.File
import java.util.Locale
import java.util.concurrent.TimeUnit
import java.util.zip.GZIPInputStream

/** The shared real recordings and the stridekit CLI the replays are compared with. */
object Shared {
    /** `$STRIDEKIT_DATA`, else the `stridekit.data` property (../shared/data). */
    private val dataDir: File? =
        (System.getenv("STRIDEKIT_DATA")?.takeIf { it.isNotEmpty() } ?: System.getProperty("stridekit.data"))
            ?.let(::File)?.takeIf { it.isDirectory }

    /** A folder of the shared data, or the test is skipped saying why. */
    fun folder(rel: String): File {
        val d = dataDir?.resolve(rel)
        assumeTrue("skipping: ${d ?: "../shared/data"} not found (set STRIDEKIT_DATA)", d != null && d.isDirectory)
        return d!!
    }

    /** The CLI (`stridekit.cli`, built by scripts/test), or the test is skipped saying why. */
    fun cli(): File {
        val f = System.getProperty("stridekit.cli")?.let(::File)
        assumeTrue("skipping: the stridekit CLI ($f) is not built (cargo build -p stridekit-cli)", f != null && f.canExecute())
        return f!!
    }

    /** Runs the CLI; fails with its output when it fails. */
    fun run(vararg args: String): String {
        val p = ProcessBuilder(listOf(cli().path) + args).redirectErrorStream(true).start()
        val out = p.inputStream.bufferedReader().readText()
        check(p.waitFor(120, TimeUnit.SECONDS)) { "stridekit ${args.joinToString(" ")}: timed out" }
        check(p.exitValue() == 0) { "stridekit ${args.joinToString(" ")} exited ${p.exitValue()}:\n$out" }
        return out
    }

    fun lines(f: File): List<String> =
        (if (f.name.endsWith(".gz")) GZIPInputStream(f.inputStream()).bufferedReader() else f.bufferedReader()).use { it.readLines() }

    /** A CSV with a header: rows as maps column -> cell. */
    fun csv(f: File): List<Map<String, String>> {
        val all = f.readLines().filter { it.isNotBlank() }
        val head = all.first().split(',')
        return all.drop(1).map { row -> head.zip(row.split(',')).toMap() }
    }

    fun fmt(v: Double, digits: Int): String = String.format(Locale.ROOT, "%.${digits}f", v)

    fun tempDir(name: String): File =
        File(System.getProperty("java.io.tmpdir"), "stridekit-robolectric-$name-${ProcessHandle.current().pid()}").apply { mkdirs() }
}
